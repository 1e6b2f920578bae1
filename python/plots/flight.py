#!/usr/bin/python3
"""Draws one simulated flight written by `uascma simulate --out DIR` (the dissertation's Figs. 4.6-4.11
and 5.18-5.29 are the model).

Usage: flight.py DIR
Writes into DIR: path.png (3-D path against the plan), forces.png (thrust, drag, torques), rotors.png
(rotor thrusts and currents), battery.png (cell voltages, bus voltage, branch currents), eod.png (EOD
against the remaining flight time, RM and MM), decisions.png (CMA state, action and IMM mode over time),
and over a city map.png (buildings, landing sites, route, LandPract checkpoints, the LandASAP footprint and
the executed emergency path; Figs. 5.6, 5.24, 5.28-5.29).
"""
import csv
import json
import os
import sys

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402
import numpy as np  # noqa: E402

ACTIONS = ["NoOp", "Terminate", "LandASAP", "LandPract"]
FS = ["N", "ELASAP", "ELPRACT"]
MH = ["NF", "SF", "JF"]
MM = ["MM0", "MM1"]
BH = ["G", "M", "P"]
RM = ["RM0", "RM1"]


IMM_MODES = ["nominal"] + [f"rotor{i}_out" for i in range(1, 7)]
# The telemetry columns that hold names (telemetry.csv writes names, not codes; see sim/telemetry.h).
NAME_COLUMNS = ("cma_state", "action", "imm_mode")


def read_telemetry(path):
    """telemetry.csv as a dict of NumPy arrays: floats (empty fields NaN, "-inf" −∞) and, for the CMA state,
    the action and the IMM mode, their names (older files with integer codes are converted)."""
    with open(path, newline="") as f:
        reader = csv.reader(f)
        header = next(reader)
        rows = list(reader)
    columns = {}
    for k, name in enumerate(header):
        values = [row[k] for row in rows]
        if name in NAME_COLUMNS:
            columns[name] = np.array(values, dtype=object)
        else:
            columns[name] = np.array([float(v) if v != "" else np.nan for v in values])
    for name, names in (("action", ACTIONS), ("imm_mode", IMM_MODES)):
        columns[name] = np.array([names[int(v)] if v.lstrip("-").isdigit() else v for v in columns[name]], dtype=object)
    columns["cma_state"] = np.array([state_label(v) if v.isdigit() else v for v in columns["cma_state"]], dtype=object)
    return columns


def state_label(index):
    index = int(index)
    rm = index % 2
    index //= 2
    bh = index % 3
    index //= 3
    mm = index % 2
    index //= 2
    mh = index % 3
    fs = index // 3
    return f"{FS[fs]},{MH[mh]},{MM[mm]},{BH[bh]},{RM[rm]}"


def events_on(ax, summary):
    for name, key in (("spall", "spall_onset_s"), ("jam", "jam_time_s"), ("isolated", "isolation_time_s")):
        if summary.get(key) is not None:
            ax.axvline(summary[key], color="grey", linestyle=":", linewidth=1)
            ax.text(summary[key], ax.get_ylim()[1], " " + name, fontsize=7, va="top", color="grey")
    for action in summary.get("actions", []):
        ax.axvline(action["time_s"], color="purple", linestyle="--", linewidth=1)


def save(fig, folder, name, axes=None, summary=None, title=None):
    """Marks the fault events and actions on time-series axes, titles the figure, writes it and closes it."""
    if axes is not None:
        if summary is not None:
            for ax in axes:
                events_on(ax, summary)
        axes[0].set_title(title)
    fig.tight_layout()
    fig.savefig(os.path.join(folder, name), dpi=110)
    plt.close(fig)


def main(folder):
    t = read_telemetry(os.path.join(folder, "telemetry.csv"))
    plan = np.genfromtxt(os.path.join(folder, "plan.csv"), delimiter=",", names=True, dtype=None, encoding="utf-8")
    with open(os.path.join(folder, "summary.json")) as f:
        summary = json.load(f)
    title = f"{summary['scenario']} — {summary['policy']}: {summary['outcome']}"
    time = t["t_s"]

    # 3-D path (altitude up) against the plan.
    fig = plt.figure(figsize=(8, 6))
    ax = fig.add_subplot(projection="3d")
    nominal = plan[plan["kind"] == "nominal"]
    ax.plot(nominal["y_m"], nominal["x_m"], -nominal["z_m"], "k--", linewidth=1, label="plan")
    emergency = plan[plan["kind"] == "emergency"]
    if len(emergency):
        ax.plot(emergency["y_m"], emergency["x_m"], -emergency["z_m"], "g--", linewidth=1, label="emergency plan")
    ax.plot(t["p_W_y_m"], t["p_W_x_m"], -t["p_W_z_m"], "b", linewidth=1.2, label="flown")
    ax.set_xlabel("east (m)")
    ax.set_ylabel("north (m)")
    ax.set_zlabel("altitude (m)")
    ax.legend()
    ax.set_title(title)
    save(fig, folder, "path.png")

    # Forces and torques.
    fig, axes = plt.subplots(3, 1, figsize=(9, 8), sharex=True)
    axes[0].plot(time, t["thrust_cmd_n"], label="thrust commanded")
    axes[0].plot(time, t["thrust_n"], label="thrust achieved")
    axes[0].set_ylabel("N")
    axes[0].legend(fontsize=8)
    drag = np.sqrt(t["drag_W_x_n"] ** 2 + t["drag_W_y_n"] ** 2 + t["drag_W_z_n"] ** 2)
    axes[1].plot(time, drag, label="|drag|")
    axes[1].set_ylabel("N")
    axes[1].legend(fontsize=8)
    for axis in "xyz":
        axes[2].plot(time, t[f"torque_{axis}_nm"], label=f"τ{axis}")
    axes[2].set_ylabel("N·m")
    axes[2].set_xlabel("time (s)")
    axes[2].legend(fontsize=8)
    save(fig, folder, "forces.png", axes, summary, title)

    # Rotor thrusts and currents.
    fig, axes = plt.subplots(2, 1, figsize=(9, 7), sharex=True)
    for i in range(1, 7):
        axes[0].plot(time, t[f"rotor{i}_thrust_n"], label=f"rotor {i}", linewidth=1)
        axes[1].plot(time, t[f"rotor{i}_current_a"], label=f"rotor {i}", linewidth=1)
    axes[0].set_ylabel("thrust (N)")
    axes[1].set_ylabel("current (A)")
    axes[1].set_xlabel("time (s)")
    axes[0].legend(fontsize=7, ncol=6)
    save(fig, folder, "rotors.png", axes, summary, title)

    # Battery.
    fig, axes = plt.subplots(3, 1, figsize=(9, 8), sharex=True)
    for pack in (1, 2):
        for cell in (1, 2, 3):
            axes[0].plot(time, t[f"cell_p{pack}c{cell}_v"], label=f"pack {pack} cell {cell}", linewidth=1)
    axes[0].axhline(3.3, color="red", linestyle="--", linewidth=1, label="cut-off 3.3 V")
    axes[0].set_ylabel("cell voltage (V)")
    axes[0].legend(fontsize=7, ncol=4)
    axes[1].plot(time, t["bus_voltage_v"])
    axes[1].set_ylabel("bus voltage (V)")
    axes[2].plot(time, t["pack_current_a"], label="total")
    axes[2].plot(time, t["branch1_current_a"], label="pack 1")
    axes[2].plot(time, t["branch2_current_a"], label="pack 2")
    axes[2].set_ylabel("current (A)")
    axes[2].set_xlabel("time (s)")
    axes[2].legend(fontsize=8)
    save(fig, folder, "battery.png", axes, None, title)

    # EOD against the remaining flight time (Figs. 4.8b, 5.2x).
    fig, axes = plt.subplots(2, 1, figsize=(9, 6), sharex=True)
    axes[0].plot(time, t["eod_s"], label="EOD")
    axes[0].plot(time, t["flight_time_remaining_s"], "k", linewidth=2, label="remaining flight time")
    axes[0].set_ylabel("s")
    axes[0].set_ylim(0, 3 * max(1.0, float(np.max(t["flight_time_remaining_s"]))))
    axes[0].legend(fontsize=8)
    axes[1].plot(time, t["reach_margin"], label="RM")
    mm = np.clip(t["motor_margin"], -1.5, 1.0)
    axes[1].plot(time, mm, label="MM (clipped at −1.5)")
    axes[1].axhline(0, color="k", linewidth=0.8)
    axes[1].set_ylabel("margin")
    axes[1].set_xlabel("time (s)")
    axes[1].legend(fontsize=8)
    save(fig, folder, "eod.png", axes, summary, title)

    # Decision timeline.
    fig, axes = plt.subplots(3, 1, figsize=(9, 7), sharex=True)
    states = t["cma_state"].tolist()
    unique = sorted(set(states))
    axes[0].step(time, [unique.index(s) for s in states], where="post")
    axes[0].set_yticks(range(len(unique)))
    axes[0].set_yticklabels(unique, fontsize=7)
    axes[0].set_ylabel("CMA state")
    axes[1].step(time, [ACTIONS.index(a) for a in t["action"]], where="post", color="purple")
    axes[1].set_yticks(range(4))
    axes[1].set_yticklabels(ACTIONS, fontsize=8)
    axes[1].set_ylabel("last action")
    axes[2].step(time, [IMM_MODES.index(m) for m in t["imm_mode"]], where="post", color="darkorange")
    axes[2].set_yticks(range(7))
    axes[2].set_yticklabels(["nominal"] + [f"rotor {i} out" for i in range(1, 7)], fontsize=7)
    axes[2].set_ylabel("IMM mode")
    axes[2].set_xlabel("time (s)")
    save(fig, folder, "decisions.png", axes, summary, title)

    draw_map(folder, t, plan, summary, title)


def draw_map(folder, t, plan, summary, title):
    path = os.path.join(folder, "map.json")
    if not os.path.exists(path):
        return
    with open(path) as f:
        city = json.load(f)
    from matplotlib.patches import Polygon  # noqa: E402
    fig, ax = plt.subplots(figsize=(9, 9))
    top = max([b["height_m"] for b in city["buildings"]] + [1.0])
    for building in city["buildings"]:
        shade = 0.9 - 0.6 * building["height_m"] / top
        for ring in building["rings"]:
            ax.add_patch(Polygon([(p[1], p[0]) for p in ring], closed=True, facecolor=(shade, shade, shade),
                                 edgecolor="grey", linewidth=0.3))
    if city["sites"]:
        ax.scatter([s["y_m"] for s in city["sites"]], [s["x_m"] for s in city["sites"]],
                   c=[s["risk"] for s in city["sites"]], cmap="RdYlGn_r", vmin=0, vmax=1, s=10, zorder=3,
                   label="landing sites (colour: risk)")
    nominal = plan[plan["kind"] == "nominal"]
    ax.plot(nominal["y_m"], nominal["x_m"], "k--", linewidth=1, label="original plan", zorder=4)
    ax.plot(t["p_W_y_m"], t["p_W_x_m"], "b", linewidth=1.2, label="flown", zorder=5)
    emergency = plan[plan["kind"] == "emergency"]
    if len(emergency):
        ax.plot(emergency["y_m"], emergency["x_m"], "g-", linewidth=2, alpha=0.6, label="emergency plan", zorder=4)
        ax.plot(emergency["y_m"][-1], emergency["x_m"][-1], "rx", markersize=12, mew=3,
                label="site: " + city.get("emergency_site", ""), zorder=6)
    if city["checkpoints"]:
        ax.plot([c[1] for c in city["checkpoints"]], [c[0] for c in city["checkpoints"]], "*", color="gold",
                markeredgecolor="k", markersize=14, label="LandPract checkpoints", zorder=6)
    if city["footprint"]:
        ys = [p[1] for p in city["footprint"]] + [city["footprint"][0][1]]
        xs = [p[0] for p in city["footprint"]] + [city["footprint"][0][0]]
        ax.plot(ys, xs, color="darkorange", linewidth=2, label="LandASAP footprint", zorder=5)
    ax.set_aspect("equal")
    ax.set_xlabel("east (m)")
    ax.set_ylabel("north (m)")
    ax.legend(fontsize=8, loc="best")
    ax.set_title(title)
    save(fig, folder, "map.png")


if __name__ == "__main__":
    if len(sys.argv) != 2:
        sys.exit(__doc__)
    main(sys.argv[1])
