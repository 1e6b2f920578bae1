#!/usr/bin/python3
"""Draws one battery case-study scenario as Figs. 4.8-4.11 of the dissertation do.

Usage: battery_case.py SCENARIO.json OUT.png
SCENARIO.json is one entry of `uascma battery case-study N --json` plus "csv" (the 1 Hz epochs written by
--out) and "case". Panel (a): total current and the current of each branch (and, under pi*, the switch
action); panel (b): each pack's EOD against the remaining flight time, the end of the mission dashed.
"""
import csv
import json
import sys

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402

ACTION_LEVEL = {"UseBatt1": 1, "UseBatt2": 2, "UseBoth": 3}


def main(source, target):
    with open(source) as f:
        scenario = json.load(f)
    with open(scenario["csv"]) as f:
        rows = list(csv.DictReader(f))
    t = [float(r["time_s"]) for r in rows]
    panels = 3 if scenario["controller"] != "UseBoth" else 2
    fig, axes = plt.subplots(panels, 1, figsize=(9, 3.2 * panels), sharex=True)
    ax = axes[0]
    ax.plot(t, [float(r["total_current_a"]) for r in rows], label="total", color="black", linewidth=1)
    ax.plot(t, [float(r["branch1_current_a"]) for r in rows], label="branch 1 (Batt1)", linewidth=1)
    ax.plot(t, [float(r["branch2_current_a"]) for r in rows], label="branch 2 (Batt2)", linewidth=1)
    ax.set_ylabel("current (A)")
    ax.legend(fontsize=8)
    ax.set_title(f"Case study {scenario['case']} {scenario['name']} {scenario['controller']}: "
                 f"{scenario['outcome']} at {scenario['end_time_s']:.0f} s")
    ax = axes[1]
    ax.plot(t, [float(r["eod1_s"]) for r in rows], label="EOD Batt1")
    ax.plot(t, [float(r["eod2_s"]) for r in rows], label="EOD Batt2")
    ax.plot(t, [float(r["remaining_flight_s"]) for r in rows], label="remaining flight time", color="black",
            linewidth=2.5)
    ax.axvline(scenario["plan_duration_s"], linestyle="-.", color="grey", label="end of mission")
    ax.set_ylabel("time (s)")
    ax.legend(fontsize=8)
    if panels == 3:
        ax = axes[2]
        ax.step(t, [ACTION_LEVEL[r["action"]] for r in rows], where="post")
        ax.set_yticks([1, 2, 3])
        ax.set_yticklabels(["UseBatt1", "UseBatt2", "UseBoth"])
        ax.set_ylabel("pi* action")
    axes[-1].set_xlabel("flight time (s)")
    fig.tight_layout()
    fig.savefig(target, dpi=110)


if __name__ == "__main__":
    if len(sys.argv) != 3:
        sys.exit("usage: battery_case.py SCENARIO.json OUT.png")
    main(sys.argv[1], sys.argv[2])
