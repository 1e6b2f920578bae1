#!/usr/bin/python3
"""Draws a CMA policy in the quadrant view of Fig. 5.9 of the dissertation.

Usage: policy_quadrants.py QUADRANTS.json OUT.png
QUADRANTS.json is `uascma policy show POLICY --json`: rows FS x MH x BH, each with quadrants I..IV.
"""
import json
import sys

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402
from matplotlib.patches import Patch, Rectangle  # noqa: E402

ACTION_COLOURS = {
    "NoOp": "#4caf50",
    "LandPract": "#2196f3",
    "LandASAP": "#ff9800",
    "Terminate": "#e53935",
}
QUADRANTS = ["I", "II", "III", "IV"]
QUADRANT_TITLES = ["I safe\nRM1 MM1", "II hazardous\nRM1 MM0", "III hyper-critical\nRM0 MM0",
                   "IV critical\nRM0 MM1"]


def main(source, target):
    with open(source) as f:
        view = json.load(f)
    rows = view["rows"]
    statuses = ["N", "ELASAP", "ELPRACT"]
    fig, axes = plt.subplots(1, 3, figsize=(15, 5.5), sharey=True)
    for panel, fs in enumerate(statuses):
        ax = axes[panel]
        panel_rows = [r for r in rows if r["I"]["state"].split(",")[0] == fs]
        for y, row in enumerate(panel_rows):
            for x, quadrant in enumerate(QUADRANTS):
                action = row[quadrant]["action"]
                ax.add_patch(Rectangle((x, y), 1, 1, facecolor=ACTION_COLOURS[action],
                                       edgecolor="white", linewidth=2))
                ax.text(x + 0.5, y + 0.5, action, ha="center", va="center", fontsize=8)
        ax.set_xlim(0, 4)
        ax.set_ylim(len(panel_rows), 0)
        ax.set_xticks([i + 0.5 for i in range(4)])
        ax.set_xticklabels(QUADRANT_TITLES, fontsize=8)
        labels = [",".join(r["I"]["state"].split(",")[1:4:2]) for r in panel_rows]
        ax.set_yticks([i + 0.5 for i in range(len(panel_rows))])
        ax.set_yticklabels(labels)
        ax.set_title(f"FS = {fs}")
        ax.tick_params(length=0)
    axes[0].set_ylabel("MH, BH")
    fig.legend(handles=[Patch(color=c, label=a) for a, c in ACTION_COLOURS.items()],
               loc="lower center", ncol=4)
    fig.suptitle(f"CMA policy by quadrant (gamma {view['gamma']}, model {view['model_hash']})")
    fig.tight_layout(rect=(0, 0.07, 1, 0.95))
    fig.savefig(target, dpi=110)


if __name__ == "__main__":
    if len(sys.argv) != 3:
        sys.exit(__doc__)
    main(sys.argv[1], sys.argv[2])
