#!/usr/bin/python3
"""Draws a battery-policy evaluation: paired flights, every policy on the same flight.

Usage: battery_evaluation.py EVALUATION.json OUT.png
EVALUATION.json is `uascma battery evaluate ... --out F.json` (or --json --runs-detail). Panel (a): completion
rate per policy with its 95 % Wilson interval; panel (b): completion per health pair and temperature; panel (c):
switches per flight (distribution, median marked).
"""
import json
import sys

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402


def main(source, target):
    with open(source) as f:
        ev = json.load(f)
    labels = ev["policies"]
    overall = ev["overall"]
    fig, axes = plt.subplots(1, 3, figsize=(18, 5.5), gridspec_kw={"width_ratios": [1, 2.2, 1.2]})

    ax = axes[0]
    rates = [o["completion_rate"] or 0.0 for o in overall]
    low = [r - (o["completion_wilson_low"] or 0.0) for r, o in zip(rates, overall)]
    high = [(o["completion_wilson_high"] or 0.0) - r for r, o in zip(rates, overall)]
    ax.bar(range(len(labels)), [100 * r for r in rates], yerr=[[100 * v for v in low], [100 * v for v in high]],
           capsize=4, color="#90caf9")
    for k, o in enumerate(overall):
        ax.text(k, 2, f"{o['completions']}/{o['runs']}", ha="center", fontsize=8)
    ax.set_xticks(range(len(labels)))
    ax.set_xticklabels(labels, rotation=20, fontsize=8)
    ax.set_ylabel("completed (%), 95 % Wilson")
    ax.set_title(f"(a) {ev['runs']} paired flights, seed {ev['seed']}")

    ax = axes[1]
    contexts = ev["by_context"]
    width = 0.8 / max(1, len(labels))
    for k, label in enumerate(labels):
        values = []
        for c in contexts:
            p = c["policies"][k]
            values.append(100.0 * p["completions"] / p["runs"] if p["runs"] else 0.0)
        ax.bar([i + k * width for i in range(len(contexts))], values, width=width, label=label)
    ax.set_xticks([i + 0.4 - width / 2 for i in range(len(contexts))])
    ax.set_xticklabels([f"{c['context']}\n(n={c['policies'][0]['runs']})" for c in contexts], rotation=60, fontsize=7)
    ax.set_ylabel("completed (%)")
    ax.set_title("(b) per health pair and temperature (Table 4.2)")
    ax.legend(fontsize=8)

    ax = axes[2]
    runs = ev.get("runs_detail", [])
    data = [[r["flights"][k]["switches"] for r in runs] for k in range(len(labels))]
    if runs:
        ax.boxplot(data, showfliers=True)
    ax.set_xticks(range(1, len(labels) + 1))
    ax.set_xticklabels(labels, rotation=20, fontsize=8)
    ax.set_ylabel("switches per flight")
    ax.set_title("(c) switches per flight (median line)")
    fig.tight_layout()
    fig.savefig(target, dpi=100)


if __name__ == "__main__":
    if len(sys.argv) != 3:
        sys.exit("usage: battery_evaluation.py EVALUATION.json OUT.png")
    main(sys.argv[1], sys.argv[2])
