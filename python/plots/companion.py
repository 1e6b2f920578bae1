#!/usr/bin/python3
"""Draws the decision log of `uascma companion --log` (docs/mavlink.md#the-cma-as-a-companion).

Usage: companion.py LOG.json OUT.png
LOG.json is written by `uascma plot companion LOG.csv`: one row per epoch of the vehicle's telemetry (the CMA state,
the policy's and the executor's action, the EOD, the remaining flight time, the reach and motor margins, the decision
time; null where the epoch was not decided) and the actions taken.
Panels over the vehicle's clock: the EOD against the remaining flight time (§5.3.1: RM compares them); the reach and
motor margins; the abstract CMA state with the actions taken marked; the decision time per epoch.
"""
import json
import sys

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402

ACTION_COLOURS = {"LandPract": "tab:orange", "LandASAP": "tab:red", "Terminate": "black"}


def series(rows, key):
    points = [(row["time_s"], row[key]) for row in rows if row[key] is not None]
    return [t for t, _ in points], [v for _, v in points]


def mark_actions(ax, actions):
    for action in actions:
        ax.axvline(action["time_s"], color=ACTION_COLOURS.get(action["action"], "tab:gray"), linestyle="--",
                   linewidth=1)


def main():
    data_path, out_path = sys.argv[1], sys.argv[2]
    with open(data_path, encoding="utf-8") as file:
        data = json.load(file)
    rows, actions = data["rows"], data["actions"]
    fig, axes = plt.subplots(4, 1, figsize=(10, 11), sharex=True)
    ax = axes[0]
    ax.plot(*series(rows, "eod_s"), label="EOD")
    ax.plot(*series(rows, "flight_time_remaining_s"), label="flight time remaining")
    ax.set_ylabel("s")
    ax.legend(loc="upper right")
    ax.set_title(f"companion decisions: {data['source']}")
    ax = axes[1]
    ax.plot(*series(rows, "reach_margin"), label="reach margin (RM)")
    ax.plot(*series(rows, "motor_margin"), label="motor margin (MM)")
    ax.axhline(0.0, color="gray", linewidth=0.8)
    ax.legend(loc="upper right")
    ax = axes[2]
    decided = [row for row in rows if row["cma_state"]]
    states = sorted({row["cma_state"] for row in decided})
    ax.plot([row["time_s"] for row in decided], [states.index(row["cma_state"]) for row in decided], ".",
            markersize=3)
    ax.set_yticks(range(len(states)))
    ax.set_yticklabels(states, fontsize=7)
    ax.set_ylabel("CMA state")
    for action in actions:
        ax.annotate(action["action"], (action["time_s"], states.index(next(
            row["cma_state"] for row in decided if row["time_s"] == action["time_s"]))),
            textcoords="offset points", xytext=(4, 4), fontsize=8,
            color=ACTION_COLOURS.get(action["action"], "tab:gray"))
    ax = axes[3]
    ax.plot([row["time_s"] for row in rows], [row["decision_ms"] for row in rows], ".", markersize=3)
    ax.set_ylabel("decision time (ms)")
    ax.set_xlabel("vehicle clock (s, SYSTEM_TIME)")
    for ax in axes:
        mark_actions(ax, actions)
        ax.grid(True, alpha=0.3)
    fig.tight_layout()
    fig.savefig(out_path, dpi=110, format="png")


if __name__ == "__main__":
    main()
