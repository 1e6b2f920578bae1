#!/usr/bin/python3
"""Draws approximate footprints of the multicopter like Fig. 5.4 of the dissertation.

Usage: footprint.py FOOTPRINTS.json OUT.png
FOOTPRINTS.json is written by `uascma footprint ... --plot OUT.png`: the initial speed, the model, and a list of
footprints (EOD, forward/backward/lateral limits, ellipse) in the heading frame (x along the velocity, y right).
Left: every footprint of the EOD sweep; right: the shortest and the longest EOD with their four limits marked.
"""
import json
import sys

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402
from matplotlib import cm  # noqa: E402
from matplotlib.patches import Ellipse  # noqa: E402


def add_footprint(ax, footprint, colour, fill=False, label=None):
    shape = footprint["shape"]
    ax.add_patch(Ellipse((shape["center_x_m"], 0.0), 2 * shape["semi_axis_x_m"], 2 * shape["semi_axis_y_m"],
                         facecolor=colour if fill else "none", edgecolor=colour, alpha=0.35 if fill else 1.0,
                         linewidth=1.5, label=label))
    if fill:
        ax.add_patch(Ellipse((shape["center_x_m"], 0.0), 2 * shape["semi_axis_x_m"], 2 * shape["semi_axis_y_m"],
                             facecolor="none", edgecolor=colour, linewidth=1.5))


def mark_limits(ax, footprint):
    centre = footprint["shape"]["center_x_m"]
    lateral = footprint["lateral_m"]
    ax.plot([footprint["forward_m"]], [0], "v", color="tab:green", label="forward limit")
    ax.plot([footprint["backward_m"]], [0], "^", color="tab:red", label="backward limit")
    ax.plot([centre, centre], [-lateral, lateral], "s", color="tab:purple", label="lateral limits")


def draw_vehicle(ax, speed, scale):
    ax.plot([0], [0], "ko", markersize=5, label="vehicle")
    if speed > 0:
        ax.annotate("", xy=(scale, 0), xytext=(0, 0), arrowprops={"arrowstyle": "->", "color": "k"})


def frame(ax, footprints):
    reach = max(max(abs(f["forward_m"]), abs(f["backward_m"]), f["lateral_m"]) for f in footprints)
    low = min(0.0, min(f["backward_m"] for f in footprints))
    high = max(0.0, max(f["forward_m"] for f in footprints))
    lateral = max(f["lateral_m"] for f in footprints)
    pad = 0.08 * max(reach, 1e-3)
    ax.set_xlim(low - pad, high + pad)
    ax.set_ylim(-lateral - pad, lateral + pad)
    ax.set_aspect("equal", adjustable="datalim")
    ax.set_xlabel("x (m, along the velocity)")
    ax.set_ylabel("y (m, right of the velocity)")
    ax.grid(True, alpha=0.3)
    return reach


def main(source, target):
    with open(source) as f:
        data = json.load(f)
    footprints = data["footprints"]
    speed = data["speed_mps"]
    fig = plt.figure(figsize=(13, 6.5))
    grid = fig.add_gridspec(2, 2, width_ratios=(1.6, 1))
    sweep = fig.add_subplot(grid[:, 0])
    colours = cm.viridis([i / max(len(footprints) - 1, 1) for i in range(len(footprints))])
    for footprint, colour in zip(footprints, colours):
        add_footprint(sweep, footprint, colour, label=f"EOD {footprint['eod_s']:g} s")
    reach = frame(sweep, footprints)
    draw_vehicle(sweep, speed, 0.1 * reach)
    sweep.set_title(f"Footprints for EOD {footprints[0]['eod_s']:g}-{footprints[-1]['eod_s']:g} s, "
                    f"v_init {speed:g} m/s ({data['model']})")
    sweep.legend(fontsize=7, loc="upper left", ncol=2)
    for row, footprint in enumerate((footprints[0], footprints[-1])):
        ax = fig.add_subplot(grid[row, 1])
        add_footprint(ax, footprint, "tab:blue", fill=True)
        mark_limits(ax, footprint)
        single_reach = frame(ax, [footprint])
        draw_vehicle(ax, speed, 0.1 * single_reach)
        ax.set_title(f"EOD {footprint['eod_s']:g} s", fontsize=10)
        if row == 0:
            ax.legend(fontsize=7, loc="best")
    fig.tight_layout()
    fig.savefig(target, dpi=110)


if __name__ == "__main__":
    if len(sys.argv) != 3:
        sys.exit(__doc__)
    main(sys.argv[1], sys.argv[2])
