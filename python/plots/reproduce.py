#!/usr/bin/python3
"""Draws the figures of `uascma reproduce` (src/reproduce): one PNG per figure spec.

Usage: reproduce.py FIGURES.json OUT_DIR
FIGURES.json: a list of specs, each {"file": "x.png", "caption": str, "kind": ...} with, by kind,
  bars:     {"bars": [{"label", "ours", "theirs"?}], "ylabel"}
  groups:   {"categories": [...], "series": [{"label", "values", "errors"?}], "ylabel",
             "theirs"?: [{"category", "series", "value"}]}
  lines:    {"series": [{"label", "x", "y", "dashed"?}], "xlabel", "ylabel", "hlines"?: [...], "vline"?: x}
  grid:     {"rows": [...], "cols": [...], "cells": [[action, ...], ...]}  (the CMA policy by quadrant)
  timeline: {"rows": [{"label", "events": [{"t", "label"}]}]}
  quantiles: {"quantiles": {"p05", "p50", "p95", "mean"?}, "xlabel"}  (a distribution's spread, not bars from 0)
"""
import json
import os
import sys
import textwrap

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402

OURS = "#1565c0"
THEIRS = "#c62828"
# The actions in the colours `uascma policy show` draws them in (policy_quadrants.py), one palette for both.
from policy_quadrants import ACTION_COLOURS  # noqa: E402


def text_colour(fill):
    """Black on a light fill, white on a dark one (the fill's relative luminance, sRGB weights, below 0.4)."""
    r, g, b = matplotlib.colors.to_rgb(fill)
    return "white" if 0.2126 * r + 0.7152 * g + 0.0722 * b < 0.4 else "black"


def bars(spec, ax):
    items = spec["bars"]
    xs = range(len(items))
    has_theirs = any("theirs" in b for b in items)
    width = 0.38 if has_theirs else 0.6
    ax.bar([x - (width / 2 if has_theirs else 0) for x in xs], [b["ours"] for b in items], width, color=OURS,
           label="ours")
    if has_theirs:
        ax.bar([x + width / 2 for x in xs], [b.get("theirs", 0) for b in items], width, color=THEIRS,
               label="dissertation")
        ax.legend(loc="upper left", bbox_to_anchor=(1.01, 1.0))
    ax.set_xticks(list(xs))
    ax.set_xticklabels([b["label"] for b in items], rotation=20, ha="right")
    ax.set_ylabel(spec.get("ylabel", ""))


def groups(spec, ax):
    categories = spec["categories"]
    series = spec["series"]
    width = 0.8 / len(series)
    for k, s in enumerate(series):
        xs = [i - 0.4 + width * (k + 0.5) for i in range(len(categories))]
        ax.bar(xs, s["values"], width, yerr=s.get("errors"), capsize=4, label=s["label"])
        for theirs in spec.get("theirs", []):
            if theirs["series"] == k:
                x = xs[categories.index(theirs["category"])]
                ax.plot([x], [theirs["value"]], marker="D", color=THEIRS, markersize=8, linestyle="none")
    if spec.get("theirs"):
        ax.plot([], [], marker="D", color=THEIRS, linestyle="none", label="dissertation")
    ax.set_xticks(range(len(categories)))
    ax.set_xticklabels(categories)
    ax.set_xlabel("battery health")
    ax.set_ylabel(spec.get("ylabel", ""))
    ax.legend(loc="upper left", bbox_to_anchor=(1.01, 1.0))


def lines(spec, ax):
    for s in spec["series"]:
        ax.plot(s["x"], s["y"], "--" if s.get("dashed") else "-", marker=".", label=s["label"])
    for y in spec.get("hlines", []):
        ax.axhline(y, color=THEIRS, linestyle=":", linewidth=1)
    if "vline" in spec:
        ax.axvline(spec["vline"], color="#555555", linestyle=":", linewidth=1)
    ax.set_xlabel(spec.get("xlabel", ""))
    ax.set_ylabel(spec.get("ylabel", ""))
    ax.legend(loc="upper left", bbox_to_anchor=(1.01, 1.0), fontsize=8)


def grid(spec, fig):
    rows, cols, cells = spec["rows"], spec["cols"], spec["cells"]
    fig.set_size_inches(7.5, 0.28 * len(rows) + 1.2)
    ax = fig.add_subplot(111)
    for i, row in enumerate(cells):
        for j, action in enumerate(row):
            fill = ACTION_COLOURS.get(action, "#dddddd")
            ax.add_patch(plt.Rectangle((j, len(rows) - 1 - i), 1, 1, color=fill))
            ax.text(j + 0.5, len(rows) - 0.5 - i, action, ha="center", va="center", fontsize=8,
                    color=text_colour(fill))
    ax.set_xlim(0, len(cols))
    ax.set_ylim(0, len(rows))
    ax.set_xticks([j + 0.5 for j in range(len(cols))])
    ax.set_xticklabels(cols)
    ax.xaxis.tick_top()
    ax.set_yticks([len(rows) - 0.5 - i for i in range(len(rows))])
    ax.set_yticklabels(rows, fontsize=8)
    ax.set_ylabel("FS, MH, BH")


def timeline(spec, ax):
    rows = spec["rows"]
    for i, row in enumerate(rows):
        y = len(rows) - 1 - i
        ts = [e["t"] for e in row["events"]]
        ax.plot(ts, [y] * len(ts), "o", color=OURS if i == 0 else THEIRS)
        for k, e in enumerate(row["events"]):
            ax.annotate(e["label"], (e["t"], y), xytext=(0, 10 + 12 * (k % 2)), textcoords="offset points",
                        ha="center", fontsize=8)
    ax.set_yticks(range(len(rows)))
    ax.set_yticklabels([r["label"] for r in reversed(rows)])
    ax.set_ylim(-0.6, len(rows) - 0.2)
    ax.set_xlabel("time (s)")


def quantiles(spec, ax):
    """The 5-95 % range as a line with end caps, the median a bar across it, the mean a diamond: a distribution
    drawn where it lies (bars from 0 made a quantile look like an amount)."""
    q = spec["quantiles"]
    ax.plot([q["p05"], q["p95"]], [0, 0], "-", color=OURS, linewidth=2, label="5-95 % range")
    ax.plot([q["p05"], q["p95"]], [0, 0], "|", color=OURS, markersize=18, markeredgewidth=2)
    ax.plot([q["p50"]], [0], "|", color="black", markersize=28, markeredgewidth=3, label="median")
    if "mean" in q:
        ax.plot([q["mean"]], [0], "D", color=THEIRS, markersize=8, linestyle="none", label="mean")
    span = q["p95"] - q["p05"]
    ax.set_xlim(q["p05"] - 0.15 * span, q["p95"] + 0.15 * span)
    ax.set_ylim(-1, 1)
    ax.set_yticks([])
    ax.set_xlabel(spec.get("xlabel", ""))
    ax.legend(loc="upper left", bbox_to_anchor=(1.01, 1.0), fontsize=8)


def draw(spec, out_dir):
    fig = plt.figure(figsize=(9, 4.2), layout="constrained")
    kind = spec["kind"]
    if kind == "grid":
        grid(spec, fig)
    else:
        ax = fig.add_subplot(111)
        {"bars": bars, "groups": groups, "lines": lines, "timeline": timeline, "quantiles": quantiles}[kind](spec, ax)
        ax.grid(True, alpha=0.3)
    fig.suptitle(textwrap.fill(spec.get("caption", ""), 110), fontsize=9)
    fig.savefig(os.path.join(out_dir, spec["file"]), dpi=90)
    plt.close(fig)


def main(source, out_dir):
    with open(source) as f:
        specs = json.load(f)
    for spec in specs:
        draw(spec, out_dir)


if __name__ == "__main__":
    if len(sys.argv) != 3:
        sys.exit("usage: reproduce.py FIGURES.json OUT_DIR")
    main(sys.argv[1], sys.argv[2])
