#!/usr/bin/python3
"""Draws the drag table `uascma identify drag --plot` made from wind-tunnel rows of the bare airframe (§2.5.3.2,
docs/identification.md#drag-table): the table's drag against airspeed, one line per pitch, over the bare-airframe
rows it was reduced from (before their speeds were grouped and carried to the group's speed as v²).

Usage: drag_table.py DATA.json OUT.png
DATA.json: {"title": str, "airspeeds_mps": [...], "zero_speed_added": bool, "bare_rows": int,
"powered_rows": int, "pitches": [{"pitch_deg": number, "drag_n": [...] (one per airspeed),
"rows": {"airspeed_mps": [...], "drag_n": [...]}}]}.
"""
import json
import sys

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402
from matplotlib import cm  # noqa: E402


def main(source, target):
    with open(source) as f:
        data = json.load(f)
    pitches = data["pitches"]
    colours = cm.viridis([i / max(len(pitches) - 1, 1) for i in range(len(pitches))])
    fig, ax = plt.subplots(figsize=(10, 6), layout="constrained")
    for pitch, colour in zip(pitches, colours):
        ax.plot(data["airspeeds_mps"], pitch["drag_n"], "-", color=colour, linewidth=1.4,
                label=f"table, pitch {pitch['pitch_deg']:g}°")
        ax.plot(pitch["rows"]["airspeed_mps"], pitch["rows"]["drag_n"], "o", color=colour, markersize=4,
                markerfacecolor="none")
    ax.plot([], [], "o", color="#616161", markerfacecolor="none", label="bare-airframe rows")
    ax.set_xlabel("airspeed (m/s)")
    ax.set_ylabel("drag along the flow (N)")
    note = " (0 m/s added: no flow, no drag)" if data["zero_speed_added"] else ""
    ax.set_title(f"{data['bare_rows']} bare rows ({data['powered_rows']} powered left out), "
                 f"{len(data['airspeeds_mps'])} speeds{note} x {len(pitches)} pitches", fontsize=10)
    ax.grid(alpha=0.3)
    # Beside the axes, never over the lines.
    ax.legend(loc="upper left", bbox_to_anchor=(1.01, 1.0), borderaxespad=0.0, fontsize=8)
    fig.suptitle(data["title"])
    fig.savefig(target, dpi=110)


if __name__ == "__main__":
    if len(sys.argv) != 3:
        sys.exit(__doc__)
    main(sys.argv[1], sys.argv[2])
