#!/usr/bin/python3
"""Draws one simulated flight written by `uascma simulate --out DIR` (the dissertation's Figs. 4.6-4.11
and 5.18-5.29 are the model).

Usage: flight.py DIR
Writes into DIR: path.png (3-D path against the plan, with the LandPract checkpoints and the buildings near
the route over a city), states.png (position, velocity and attitude with the motor fault flag, Fig. 5.19),
forces.png (thrust, drag, torques), rotors.png
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


EVENTS = (("spall", "spall_onset_s"), ("jam", "jam_time_s"), ("isolated", "isolation_time_s"))
LABEL_ROW_PT = 9  # ours: one row of event labels above the top axes (8 pt text and a 1 pt gap)


def events_on(ax, summary, labelled):
    """Marks the fault events (dotted grey) and executed actions (dashed purple) on a time-series axes. On the
    `labelled` (top) axes the names sit above the frame, each on the lowest row where its box (matplotlib's own
    extent) meets no earlier label, so events seconds apart (a jam and its isolation) never overprint."""
    marks = [(summary[key], name, "grey", ":") for name, key in EVENTS if summary.get(key) is not None]
    marks += [(a["time_s"], a["action"], "purple", "--") for a in summary.get("actions", [])]
    for time_s, _, colour, style in marks:
        ax.axvline(time_s, color=colour, linestyle=style, linewidth=1)
    if not labelled:
        return 0
    renderer = ax.figure.canvas.get_renderer()
    placed = []  # (row, box)
    rows = 0
    for time_s, name, colour, _ in sorted(marks):
        row = 0
        while True:
            label = ax.annotate(name, xy=(time_s, 1.0), xycoords=ax.get_xaxis_transform(),
                                xytext=(1, 2 + row * LABEL_ROW_PT), textcoords="offset points", fontsize=8,
                                color=colour, va="bottom", ha="left", annotation_clip=False)
            box = label.get_window_extent(renderer)
            if not any(r == row and box.overlaps(b) for r, b in placed):
                placed.append((row, box))
                rows = max(rows, row + 1)
                break
            label.remove()
            row += 1
    return rows


def legend_outside(ax, **kwargs):
    """The legend to the right of the axes: never over the data."""
    kwargs.setdefault("fontsize", 8)
    return ax.legend(loc="upper left", bbox_to_anchor=(1.01, 1.0), borderaxespad=0.0, **kwargs)


def new_figure(rows, figsize):
    fig, axes = plt.subplots(rows, 1, figsize=figsize, sharex=True, layout="constrained")
    return fig, np.atleast_1d(axes)


def save(fig, folder, name, axes=None, summary=None, title=None):
    """Marks the fault events and actions on time-series axes, titles the figure, writes it and closes it."""
    if axes is not None:
        fig.canvas.draw()  # the layout, so that label extents are final
        if summary is not None:
            for k, ax in enumerate(axes):
                events_on(ax, summary, labelled=k == 0)
        fig.suptitle(title)
    elif fig.get_layout_engine() is None:
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

    city = read_city(folder)

    # 3-D path (altitude up) against the plan, with the checkpoints and the buildings near the route.
    fig = plt.figure(figsize=(9, 7))
    ax = fig.add_subplot(projection="3d")
    if city is not None:
        buildings_3d(ax, city, np.concatenate([t["p_W_x_m"], plan["x_m"]]), np.concatenate([t["p_W_y_m"], plan["y_m"]]))
        if city["checkpoints"]:
            cp = np.array(city["checkpoints"], dtype=float)
            ax.scatter(cp[:, 1], cp[:, 0], -cp[:, 2], marker="*", s=140, color="gold", edgecolor="k",
                       depthshade=False, label="LandPract checkpoints")
    nominal = plan[plan["kind"] == "nominal"]
    ax.plot(nominal["y_m"], nominal["x_m"], -nominal["z_m"], "k--", linewidth=1, label="plan")
    emergency = plan[plan["kind"] == "emergency"]
    if len(emergency):
        ax.plot(emergency["y_m"], emergency["x_m"], -emergency["z_m"], "g--", linewidth=1, label="emergency plan")
    ax.plot(t["p_W_y_m"], t["p_W_x_m"], -t["p_W_z_m"], "b", linewidth=1.2, label="flown")
    ax.set_xlabel("east (m)", labelpad=18)
    ax.set_ylabel("north (m)", labelpad=18)
    ax.set_zlabel("altitude (m)", labelpad=8)
    ax.legend(loc="upper left", bbox_to_anchor=(0.0, 1.0), fontsize=8, bbox_transform=fig.transFigure)
    fig.suptitle(title)
    save(fig, folder, "path.png")

    # Fig. 5.19: the vehicle's states, with the motor fault flag (the IMM's isolation) as a step.
    fault = np.array([0.0 if m == "nominal" else 1.0 for m in t["imm_mode"]])
    fig, axes = new_figure(3, (10, 8))
    groups = (
        ("position (m)", (("p_W_x_m", "north", 1.0), ("p_W_y_m", "east", 1.0), ("p_W_z_m", "altitude", -1.0))),
        ("velocity (m/s)", (("v_W_x_mps", "north", 1.0), ("v_W_y_mps", "east", 1.0), ("v_W_z_mps", "up", -1.0))),
        ("attitude (deg)", (("roll_rad", "roll", 180 / np.pi), ("pitch_rad", "pitch", 180 / np.pi),
                            ("yaw_rad", "yaw (unwrapped)", 180 / np.pi))),
    )
    for ax, (ylabel, series) in zip(axes, groups):
        for column, name, scale in series:
            values = np.unwrap(t[column]) if column == "yaw_rad" else t[column]  # no ±180° jumps
            ax.plot(time, scale * values, linewidth=1.1, label=name)
        ax.set_ylabel(ylabel)
        flag = ax.twinx()
        flag.step(time, fault, where="post", color="red", linewidth=1.2, label="motor fault flag")
        flag.set_ylim(-0.05, 1.6)
        flag.set_yticks([0, 1])
        flag.set_ylabel("fault flag", color="red")
        lines = ax.get_lines() + flag.get_lines()
        ax.legend(lines, [line.get_label() for line in lines], loc="upper left", bbox_to_anchor=(1.08, 1.0),
                  borderaxespad=0.0, fontsize=8)
    axes[-1].set_xlabel("time (s)")
    save(fig, folder, "states.png", axes, summary, title)

    # Forces and torques.
    fig, axes = new_figure(3, (10, 8))
    axes[0].plot(time, t["thrust_cmd_n"], label="thrust commanded")
    axes[0].plot(time, t["thrust_n"], label="thrust achieved")
    axes[0].set_ylabel("N")
    legend_outside(axes[0])
    drag = np.sqrt(t["drag_W_x_n"] ** 2 + t["drag_W_y_n"] ** 2 + t["drag_W_z_n"] ** 2)
    axes[1].plot(time, drag, label="|drag|")
    axes[1].set_ylabel("N")
    legend_outside(axes[1])
    for axis in "xyz":
        axes[2].plot(time, t[f"torque_{axis}_nm"], label=f"τ{axis}")
    axes[2].set_ylabel("N·m")
    axes[2].set_xlabel("time (s)")
    legend_outside(axes[2])
    save(fig, folder, "forces.png", axes, summary, title)

    # Rotor thrusts and currents.
    fig, axes = new_figure(2, (10, 7))
    for i in range(1, 7):
        axes[0].plot(time, t[f"rotor{i}_thrust_n"], label=f"rotor {i}", linewidth=1)
        axes[1].plot(time, t[f"rotor{i}_current_a"], label=f"rotor {i}", linewidth=1)
    axes[0].set_ylabel("thrust (N)")
    axes[1].set_ylabel("current (A)")
    axes[1].set_xlabel("time (s)")
    legend_outside(axes[0])
    save(fig, folder, "rotors.png", axes, summary, title)

    # Battery.
    fig, axes = new_figure(3, (10, 8))
    for pack in (1, 2):
        for cell in (1, 2, 3):
            axes[0].plot(time, t[f"cell_p{pack}c{cell}_v"], label=f"pack {pack} cell {cell}", linewidth=1)
    axes[0].axhline(3.3, color="red", linestyle="--", linewidth=1, label="cut-off 3.3 V")
    axes[0].set_ylabel("cell voltage (V)")
    legend_outside(axes[0])
    axes[1].plot(time, t["bus_voltage_v"])
    axes[1].set_ylabel("bus voltage (V)")
    axes[2].plot(time, t["pack_current_a"], label="total")
    axes[2].plot(time, t["branch1_current_a"], label="pack 1")
    axes[2].plot(time, t["branch2_current_a"], label="pack 2")
    axes[2].set_ylabel("current (A)")
    axes[2].set_xlabel("time (s)")
    legend_outside(axes[2])
    save(fig, folder, "battery.png", axes, None, title)

    # EOD against the remaining flight time (Figs. 4.8b, 5.2x).
    fig, axes = new_figure(2, (10, 6))
    axes[0].plot(time, t["eod_s"], label="EOD")
    axes[0].plot(time, t["flight_time_remaining_s"], "k", linewidth=2, label="remaining flight time")
    axes[0].set_ylabel("s")
    axes[0].set_ylim(0, 3 * max(1.0, float(np.max(t["flight_time_remaining_s"]))))
    legend_outside(axes[0])
    axes[1].plot(time, t["reach_margin"], label="RM")
    mm = np.clip(t["motor_margin"], -1.5, 1.0)
    axes[1].plot(time, mm, label="MM (clipped at −1.5)")
    axes[1].axhline(0, color="k", linewidth=0.8)
    axes[1].set_ylabel("margin")
    axes[1].set_xlabel("time (s)")
    legend_outside(axes[1])
    save(fig, folder, "eod.png", axes, summary, title)

    # Decision timeline.
    fig, axes = new_figure(3, (10, 7))
    states = t["cma_state"].tolist()
    unique = sorted(set(states))
    axes[0].step(time, [unique.index(s) for s in states], where="post")
    axes[0].set_yticks(range(len(unique)))
    axes[0].set_yticklabels(unique, fontsize=8)
    axes[0].set_ylabel("CMA state")
    axes[1].step(time, [ACTIONS.index(a) for a in t["action"]], where="post", color="purple")
    axes[1].set_yticks(range(4))
    axes[1].set_yticklabels(ACTIONS, fontsize=8)
    axes[1].set_ylabel("last action")
    axes[2].step(time, [IMM_MODES.index(m) for m in t["imm_mode"]], where="post", color="darkorange")
    axes[2].set_yticks(range(7))
    axes[2].set_yticklabels(["nominal"] + [f"rotor {i} out" for i in range(1, 7)], fontsize=8)
    axes[2].set_ylabel("IMM mode")
    axes[2].set_xlabel("time (s)")
    save(fig, folder, "decisions.png", axes, summary, title)

    if city is not None:
        draw_map(folder, t, plan, city, title)


def read_city(folder):
    path = os.path.join(folder, "map.json")
    if not os.path.exists(path):
        return None
    with open(path) as f:
        return json.load(f)


# Buildings drawn in the 3-D path: those within this distance of the flown path or the plans (ours: the
# LandPract/LandASAP planners' obstacles near the route; the whole city would hide the path).
NEAR_ROUTE_M = 60.0


def buildings_3d(ax, city, north_m, east_m):
    from mpl_toolkits.mplot3d.art3d import Poly3DCollection

    route = np.column_stack([north_m, east_m])
    route = route[np.all(np.isfinite(route), axis=1)][::10]
    faces = []
    for building in city["buildings"]:
        height = building["height_m"]
        for ring in building["rings"]:
            ring = np.asarray(ring, dtype=float)[:, :2]
            distance = np.min(np.linalg.norm(route[:, None, :] - ring[None, :, :], axis=2))
            if distance > NEAR_ROUTE_M:
                continue
            roof = [(p[1], p[0], height) for p in ring]
            faces.append(roof)
            for a, b in zip(ring, np.roll(ring, -1, axis=0)):
                faces.append([(a[1], a[0], 0.0), (b[1], b[0], 0.0), (b[1], b[0], height), (a[1], a[0], height)])
    if faces:
        ax.add_collection3d(Poly3DCollection(faces, facecolor=(0.6, 0.6, 0.6, 0.25), edgecolor=(0.3, 0.3, 0.3, 0.3),
                                             linewidth=0.3))
        ax.plot([], [], "s", color=(0.6, 0.6, 0.6), label=f"buildings within {NEAR_ROUTE_M:.0f} m of the route")


# The map's view: the flown path, the plans and the checkpoints with this margin around them (ours: a quarter of
# their extent, at least VIEW_MIN_HALF_M each side of their centre so that the buildings around a short route
# show). A LandASAP footprint or a city larger than that is cut by the axes, not allowed to shrink the route to a
# short stroke.
VIEW_MARGIN = 0.25
VIEW_MIN_HALF_M = 150.0


def route_view(ax, east_m, north_m):
    """Sets a square view (equal aspect) on the given points; returns (east_lo, east_hi, north_lo, north_hi)."""
    east_m, north_m = np.asarray(east_m, dtype=float), np.asarray(north_m, dtype=float)
    keep = np.isfinite(east_m) & np.isfinite(north_m)
    east_m, north_m = east_m[keep], north_m[keep]
    centre = np.array([(east_m.min() + east_m.max()) / 2, (north_m.min() + north_m.max()) / 2])
    half = max(east_m.max() - east_m.min(), north_m.max() - north_m.min()) / 2 * (1 + 2 * VIEW_MARGIN)
    half = max(half, VIEW_MIN_HALF_M)
    ax.set_xlim(centre[0] - half, centre[0] + half)
    ax.set_ylim(centre[1] - half, centre[1] + half)
    return centre[0] - half, centre[0] + half, centre[1] - half, centre[1] + half


def draw_map(folder, t, plan, city, title):
    from matplotlib.patches import Polygon  # noqa: E402
    # The key has an axes of its own beside the map: the layout then holds it whole whatever the map's aspect
    # (a legend hung outside an equal-aspect axes was cut at the figure's edge).
    fig, (ax, key) = plt.subplots(1, 2, figsize=(11, 9), layout="constrained", width_ratios=[3, 1])
    key.axis("off")
    top = max([b["height_m"] for b in city["buildings"]] + [1.0])
    for building in city["buildings"]:
        shade = 0.9 - 0.6 * building["height_m"] / top
        for ring in building["rings"]:
            ax.add_patch(Polygon([(p[1], p[0]) for p in ring], closed=True, facecolor=(shade, shade, shade),
                                 edgecolor="grey", linewidth=0.3))
    if city["sites"]:
        # Markers of one size (not to scale), drawn under the route and small enough to leave the buildings seen.
        ax.scatter([s["y_m"] for s in city["sites"]], [s["x_m"] for s in city["sites"]],
                   c=[s["risk"] for s in city["sites"]], cmap="RdYlGn_r", vmin=0, vmax=1, s=6, linewidths=0,
                   zorder=3, label="landing sites (dots not to scale; colour: risk)")
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
    east = [t["p_W_y_m"], nominal["y_m"], emergency["y_m"]] + [[c[1] for c in city["checkpoints"]]]
    north = [t["p_W_x_m"], nominal["x_m"], emergency["x_m"]] + [[c[0] for c in city["checkpoints"]]]
    east_lo, east_hi, north_lo, north_hi = route_view(ax, np.concatenate(east), np.concatenate(north))
    if city["footprint"]:
        ys = [p[1] for p in city["footprint"]] + [city["footprint"][0][1]]
        xs = [p[0] for p in city["footprint"]] + [city["footprint"][0][0]]
        inside = min(ys) >= east_lo and max(ys) <= east_hi and min(xs) >= north_lo and max(xs) <= north_hi
        ax.plot(ys, xs, color="darkorange", linewidth=2, zorder=5,
                label="LandASAP footprint" + ("" if inside else " (reaches beyond the view)"))
    ax.set_aspect("equal", adjustable="box")
    ax.set_xlabel("east (m)")
    ax.set_ylabel("north (m)")
    key.legend(*ax.get_legend_handles_labels(), loc="upper left", fontsize=8, borderaxespad=0.0)
    ax.set_title(title)
    save(fig, folder, "map.png")


if __name__ == "__main__":
    if len(sys.argv) != 2:
        sys.exit(__doc__)
    main(sys.argv[1])
