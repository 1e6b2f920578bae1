#!/usr/bin/python3
"""Draws the battery-reconfiguration policies (dissertation §4.3, Fig. 4.5's 18 leaves).

Usage: battery_policy.py VIEW.json OUT.png
VIEW.json is `uascma battery show POLICY --json`: per context (B1F, B2F, T) the action of each of the
289 states. Each panel is one context; rows are (current, pack-1 switch, energy, voltage), columns
(pack-2 switch, energy, voltage), so the 288 non-failure states fill a 24 x 12 grid.
"""
import json
import sys

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402
from matplotlib.colors import ListedColormap  # noqa: E402
from matplotlib.patches import Patch  # noqa: E402

ACTIONS = ["UseBatt1", "UseBatt2", "UseBoth"]
COLOURS = ["#2196f3", "#ff9800", "#4caf50"]


def pack_labels():
    labels = []
    for switch in ["OFF", "ON"]:
        for energy in ["S1", "S2", "S3"]:
            for voltage in ["C0", "C1"]:
                labels.append(f"{switch}{energy}{voltage}")
    return labels


def main(source, target):
    with open(source) as f:
        view = json.load(f)
    contexts = view["contexts"]
    packs = pack_labels()
    rows = [f"{current} {p}" for current in ["IL", "IH"] for p in packs]
    fig, axes = plt.subplots(3, 6, figsize=(24, 16))
    cmap = ListedColormap(COLOURS)
    for k, context in enumerate(contexts):
        ax = axes[k // 6][k % 6]
        grid = [[ACTIONS.index(context["action"][r * 12 + c]) for c in range(12)] for r in range(24)]
        ax.imshow(grid, cmap=cmap, vmin=0, vmax=2, aspect="auto")
        ax.set_title(f"{context['temperature']}  B1 {context['b1']}  B2 {context['b2']}"
                     f"  ({context['unobserved_rows']} unobserved)", fontsize=9)
        ax.set_xticks(range(12))
        ax.set_xticklabels(packs, rotation=90, fontsize=5)
        ax.set_yticks(range(24))
        ax.set_yticklabels(rows if k % 6 == 0 else [], fontsize=5)
        ax.set_xlabel("pack 2", fontsize=7)
        if k % 6 == 0:
            ax.set_ylabel("current, pack 1", fontsize=7)
    fig.legend(handles=[Patch(color=c, label=a) for a, c in zip(ACTIONS, COLOURS)], loc="lower center", ncol=3)
    fig.suptitle(f"Battery policies per context (Fig. 4.5 leaves), gamma {view['gamma']}, model {view['model_hash']}")
    fig.tight_layout(rect=(0, 0.03, 1, 0.97))
    fig.savefig(target, dpi=100)


if __name__ == "__main__":
    if len(sys.argv) != 3:
        sys.exit("usage: battery_policy.py VIEW.json OUT.png")
    main(sys.argv[1], sys.argv[2])
