#!/usr/bin/python3
"""Draws the EOD distribution's reliability diagram: per health group, the fraction of 1 Hz predictions
whose probability integral transform P(EOD_pred < EOD_true) is at most p, against p (the diagonal: calibrated), and
the coverage of the central 50/80/90/95 % intervals against their nominal probability.

Usage: eod_reliability.py CALIBRATION.json OUT.png
CALIBRATION.json (written by `uascma calibrate eod --plot`): {"groups": [{"group": "G", "samples": n, "flights": n,
"coverage": {"50": c, "80": c, "90": c, "95": c}, "report": {"reliability": [{"nominal": p, "observed": f}, ...]}},
...], "error_model": str, "campaign": str}.
"""
import json
import sys

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402

COLOURS = {"G": "#2e7d32", "M": "#f9a825", "P": "#c62828", "all": "#1565c0"}


def main(source, target):
    with open(source) as f:
        data = json.load(f)
    fig, axes = plt.subplots(1, 2, figsize=(12, 5.2), layout="constrained")
    reliability, coverage = axes
    for ax in axes:
        ax.plot([0, 1], [0, 1], color="#999999", linewidth=1, linestyle="--", label="calibrated")
    for group in data["groups"]:
        label = f"{group['group']} ({group['flights']} flights, {group['samples']} predictions)"
        colour = COLOURS.get(group["group"], "#555555")
        width = 2.2 if group["group"] == "all" else 1.4
        rows = group["report"]["reliability"]
        nominal = [row["nominal"] for row in rows]
        observed = [row["observed"] for row in rows]
        reliability.plot([0] + nominal + [1], [0] + observed + [1], marker=".", color=colour, linewidth=width,
                         label=label)
        levels = sorted(group["coverage"], key=float)
        coverage.plot([float(level) / 100 for level in levels], [group["coverage"][level] for level in levels],
                      marker="o", color=colour, linewidth=width, label=label)
    reliability.set_xlabel("p")
    reliability.set_ylabel("observed fraction of true EODs <= the predicted p quantile")
    reliability.set_title("(a) reliability")
    coverage.set_xlabel("nominal probability of the central interval")
    coverage.set_ylabel("observed coverage of the true EOD")
    coverage.set_title("(b) interval coverage")
    coverage.set_xlim(0.4, 1.0)
    coverage.set_ylim(0.4, 1.0)
    coverage.axhspan(0.85, 0.95, xmin=(0.9 - 0.4) / 0.6 - 0.01, xmax=(0.9 - 0.4) / 0.6 + 0.01, color="#cccccc")
    coverage.legend(loc="upper left", fontsize=8)
    reliability.legend(loc="upper left", fontsize=8)
    fig.suptitle(f"EOD calibration: {data.get('campaign', '')}; error table: {data.get('error_model', '')}",
                 fontsize=9)
    fig.savefig(target, dpi=130)


if __name__ == "__main__":
    if len(sys.argv) != 3:
        sys.exit(__doc__)
    main(sys.argv[1], sys.argv[2])
