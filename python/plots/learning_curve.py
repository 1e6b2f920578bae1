#!/usr/bin/python3
"""Draws the Q-learning curve of Fig. 5.14 of the dissertation: the average sum of rewards over episodes,
(a) over all episodes and (b) the same expanded after the first tenth.

Usage: learning_curve.py CURVE.json OUT.png
CURVE.json (written by `uascma learn q --plot`): {"title": str, "episode": [...], "return": [...],
"mean_return": [...], "states_visited": [...]}.
"""
import json
import sys

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402


def main(source, target):
    with open(source) as f:
        curve = json.load(f)
    episode = curve["episode"]
    mean = curve["mean_return"]
    returns = curve["return"]
    visited = curve["states_visited"]
    fig, axes = plt.subplots(1, 3, figsize=(17, 4.8), layout="constrained")
    ax = axes[0]
    ax.plot(episode, returns, ".", markersize=1.5, color="#bbbbbb", label="episode return")
    ax.plot(episode, mean, color="#1565c0", linewidth=1.5, label="average sum of rewards")
    ax.set_xlabel("episode")
    ax.set_ylabel("sum of rewards")
    ax.set_title("(a) average sum of rewards")
    # Beside the axes, not over the returns.
    ax.legend(loc="upper left", bbox_to_anchor=(1.01, 1.0), borderaxespad=0.0, fontsize=8)
    ax = axes[1]
    start = len(episode) // 10
    ax.plot(episode[start:], mean[start:], color="#1565c0", linewidth=1.5)
    ax.set_xlabel("episode")
    ax.set_ylabel("average sum of rewards")
    ax.set_title("(b) expanded view")
    ax = axes[2]
    ax.plot(episode, visited, color="#2e7d32", linewidth=1.5)
    ax.set_xlabel("episode")
    ax.set_ylabel("states visited")
    ax.set_title("learning states visited")
    fig.suptitle(curve.get("title", "Q-learning (Fig. 5.14)"))
    fig.savefig(target, dpi=110)


if __name__ == "__main__":
    if len(sys.argv) != 3:
        sys.exit(__doc__)
    main(sys.argv[1], sys.argv[2])
