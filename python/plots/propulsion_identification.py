#!/usr/bin/python3
"""Draws a motor-propeller pair's models against its thrust-stand files (dissertation §2.5.2).

figure "identify" (`uascma identify propulsion --plot`), Fig. 2.10: (a) the measured RPM against the throttle for
each file (e.g. its 2S and 3S step tests) with eq. 2.12's surface along the file's measured power and its 95 %
prediction bounds; (b) the leave-one-step-out errors: each point predicted by the surface fitted without its
throttle step, with that surface's bounds; (c) the measured thrust against C_T RPM² (eq. 2.1) with the ±10 % band
above the check throttle.
figure "validate" (`uascma validate propulsion --plot`), Fig. 2.11: (a) the measured RPM with the model's 95 %
bounds, points outside the fitted throttle/power range flagged; (b) the thrust as in (c) above.

Usage: propulsion_identification.py DATA.json OUT.png
DATA.json: {"figure": "identify" | "validate", "title": str, "thrust_check_above_us": number,
"thrust_band_fraction": number, "files": [{"name": str, "throttle_us": [...], "power_w": [...], "rpm": [...],
"predicted_rpm": [...], "lower_rpm": [...], "upper_rpm": [...], "thrust_n": [...], "predicted_thrust_n": [...]
(C_T RPM² at the measured RPM), "in_range": [bool...], "thrust_band": {"throttle_us", "low_n", "high_n"},
 identify only: "loo_error_percent": [...] (predicted − measured, % of measured), "loo_bound_percent": [...],
 "loo_within_bounds": [bool...]}],
 identify: "loo_rpm_median_relative_error", "loo_rpm_max_relative_error", "loo_share_within_95_bounds",
   "thrust_median_relative_error", "thrust_max_relative_error";
 validate: "points", "out_of_range", "share_within_95_bounds", "rpm_median_relative_error",
   "rpm_max_relative_error", "thrust_median_relative_error"}.
"""
import os

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402

import figure_choice  # noqa: E402

COLOURS = ["#1565c0", "#e53935", "#2e7d32", "#6a1b9a", "#ef6c00", "#00838f"]


def legend_below(ax):
    # Under the axes, never over the points (each file adds three entries).
    ax.legend(loc="upper center", bbox_to_anchor=(0.5, -0.13), borderaxespad=0.0, fontsize=8, ncol=2)


def name(file):
    return os.path.basename(file["name"])


def draw_rpm(ax, data, flag_out_of_range):
    for file, colour in zip(data["files"], COLOURS * len(data["files"])):
        throttle = file["throttle_us"]
        ax.fill_between(throttle, file["lower_rpm"], file["upper_rpm"], color=colour, alpha=0.15, linewidth=0,
                        label=f"{name(file)}: 95 % bounds")
        ax.plot(throttle, file["predicted_rpm"], "-", color=colour, linewidth=1.2,
                label=f"{name(file)}: eq. 2.12 at its power")
        inside = [k for k, ok in enumerate(file["in_range"]) if ok or not flag_out_of_range]
        ax.plot([throttle[k] for k in inside], [file["rpm"][k] for k in inside], "o", color=colour, markersize=4,
                label=f"{name(file)}: measured")
        outside = [k for k, ok in enumerate(file["in_range"]) if flag_out_of_range and not ok]
        if outside:
            ax.plot([throttle[k] for k in outside], [file["rpm"][k] for k in outside], "x", color="#000000",
                    markersize=7, label=f"{name(file)}: outside the fitted range")
    ax.set_xlabel("throttle (µs)")
    ax.set_ylabel("RPM")
    ax.grid(alpha=0.3)


def draw_loo(ax, data):
    for file, colour in zip(data["files"], COLOURS * len(data["files"])):
        ax.errorbar(file["throttle_us"], file["loo_error_percent"], yerr=file["loo_bound_percent"], fmt="o",
                    color=colour, markersize=4, capsize=2, elinewidth=0.8, label=f"{name(file)}: left out")
        missed = [k for k, ok in enumerate(file["loo_within_bounds"]) if not ok]
        if missed:
            ax.plot([file["throttle_us"][k] for k in missed], [file["loo_error_percent"][k] for k in missed], "s",
                    markerfacecolor="none", markeredgecolor="#000000", markersize=8,
                    label=f"{name(file)}: outside its bounds")
    ax.axhline(0.0, color="#9e9e9e", linewidth=0.8)
    ax.set_xlabel("throttle (µs)")
    ax.set_ylabel("RPM error, predicted − measured (%)")
    ax.set_title(f"(b) leave-one-step-out: median {100 * data['loo_rpm_median_relative_error']:.2f} %, max "
                 f"{100 * data['loo_rpm_max_relative_error']:.2f} %,\n"
                 f"{100 * data['loo_share_within_95_bounds']:.0f} % within the 95 % bounds", fontsize=10)
    ax.grid(alpha=0.3)


def draw_thrust(ax, data, title):
    band = 100 * data["thrust_band_fraction"]
    for k, (file, colour) in enumerate(zip(data["files"], COLOURS * len(data["files"]))):
        shaded = file["thrust_band"]
        ax.fill_between(shaded["throttle_us"], shaded["low_n"], shaded["high_n"], color=colour, alpha=0.15,
                        linewidth=0, label=f"{name(file)}: ±{band:.0f} % above {data['thrust_check_above_us']:g} µs")
        ax.plot(file["throttle_us"], file["predicted_thrust_n"], "-", color=colour, linewidth=1.2,
                label=f"{name(file)}: C_T RPM² (eq. 2.1)")
        ax.plot(file["throttle_us"], file["thrust_n"], "o", color=colour, markersize=4,
                label=f"{name(file)}: measured")
    ax.set_xlabel("throttle (µs)")
    ax.set_ylabel("thrust (N)")
    ax.set_title(title, fontsize=10)
    ax.grid(alpha=0.3)


def draw_identify(data):
    fig, axes = plt.subplots(1, 3, figsize=(19, 7), layout="constrained")
    draw_rpm(axes[0], data, flag_out_of_range=False)
    axes[0].set_title("(a) measured RPM and eq. 2.12 along each file's power", fontsize=10)
    legend_below(axes[0])
    draw_loo(axes[1], data)
    legend_below(axes[1])
    draw_thrust(axes[2], data, f"(c) thrust: median error {100 * data['thrust_median_relative_error']:.2f} %, "
                               f"max {100 * data['thrust_max_relative_error']:.2f} %\n"
                               f"above {data['thrust_check_above_us']:g} µs")
    legend_below(axes[2])
    fig.suptitle(data["title"])
    return fig


def draw_validate(data):
    fig, axes = plt.subplots(1, 2, figsize=(15, 7), layout="constrained")
    draw_rpm(axes[0], data, flag_out_of_range=True)
    axes[0].set_title(f"(a) {100 * data['share_within_95_bounds']:.0f} % of the measured RPM within the 95 % bounds; "
                      f"error median {100 * data['rpm_median_relative_error']:.2f} %,\n"
                      f"max {100 * data['rpm_max_relative_error']:.2f} % ({data['out_of_range']} of "
                      f"{data['points']} points outside the fitted range, left out)", fontsize=10)
    legend_below(axes[0])
    draw_thrust(axes[1], data, f"(b) thrust from C_T at the measured RPM: median error "
                               f"{100 * data['thrust_median_relative_error']:.2f} %")
    legend_below(axes[1])
    fig.suptitle(data["title"])
    return fig


if __name__ == "__main__":
    figure_choice.run(__doc__, {"identify": draw_identify, "validate": draw_validate})
