#!/usr/bin/python3
"""Fly one scenario with the CMA policy and plot it from Python (pandas + matplotlib).

    PYTHONPATH=build/python /usr/bin/python3 examples/python/fly_and_plot.py [SCENARIO.yaml] [--out flight.png]

Default scenario: examples/jam-motor-3.yaml (a spalled motor 3 jams, the IMM isolates it, the vehicle flies
on as a quadcopter and the CMA policy decides whether to land). Draws the ground track, the altitude, the
battery's EOD against the remaining flight time, and the CMA state and action over time.
"""
import argparse

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402

import uascma  # noqa: E402


def main():
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("scenario", nargs="?", default=uascma.example_file("jam-motor-3.yaml"))
    parser.add_argument("--policy", default="cma", help="noop | cma | a policy JSON file")
    parser.add_argument("--seed", type=int, default=None, help="overrides the scenario's seed")
    parser.add_argument("--out", default="flight.png")
    args = parser.parse_args()

    flight = uascma.run(args.scenario, args.policy, seed=args.seed)
    print(flight, f"after {flight.sim_time_s:.1f} s:", flight.reason)
    for time_s, what in flight.events:
        print(f"  {time_s:8.2f} s  {what}")

    t = uascma.telemetry_frame(flight)  # one row per 0.1 s, names for states and actions
    plan = flight.plan()                # (M, 4): t_s, north_m, east_m, down_m

    fig, axes = plt.subplots(2, 2, figsize=(12, 8))
    ax = axes[0, 0]
    ax.plot(plan[:, 2], plan[:, 1], "k--", linewidth=1, label="plan")
    ax.plot(t["p_W_y_m"], t["p_W_x_m"], "b", label="flown")
    ax.set_xlabel("east (m)")
    ax.set_ylabel("north (m)")
    ax.set_aspect("equal")
    ax.legend()

    ax = axes[0, 1]
    ax.plot(t["t_s"], -t["p_W_z_m"], label="altitude")
    ax.plot(t["t_s"], -t["p_ref_W_z_m"], "k--", linewidth=1, label="reference")
    ax.set_xlabel("time (s)")
    ax.set_ylabel("m")
    ax.legend()

    ax = axes[1, 0]
    ax.plot(t["t_s"], t["eod_s"], label="EOD")
    ax.plot(t["t_s"], t["flight_time_remaining_s"], "k", label="remaining flight time")
    ax.plot(t["t_s"], t["rul_s"], "r", label="motor RUL (NaN before the spall)")
    ax.set_ylim(0, 3 * max(1.0, t["flight_time_remaining_s"].max()))
    ax.set_xlabel("time (s)")
    ax.set_ylabel("s")
    ax.legend(fontsize=8)

    ax = axes[1, 1]
    states = sorted(t["cma_state"].unique())
    ax.step(t["t_s"], t["cma_state"].map(states.index), where="post", label="CMA state")
    ax.set_yticks(range(len(states)))
    ax.set_yticklabels(states, fontsize=7)
    for time_s, action in flight.actions:
        ax.axvline(time_s, color="purple", linestyle="--")
        ax.text(time_s, len(states) - 1, " " + action, color="purple", fontsize=8, va="top")
    ax.set_xlabel("time (s)")

    fig.suptitle(f"{flight.scenario.name}, policy {flight.policy}: {flight.outcome}")
    fig.tight_layout()
    fig.savefig(args.out, dpi=100)
    print("wrote", args.out)


if __name__ == "__main__":
    main()
