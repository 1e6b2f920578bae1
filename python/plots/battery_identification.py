#!/usr/bin/python3
"""Draws an identified cell against its record (dissertation §3.3.1.1).

figure "identify" (`uascma identify battery --plot`): the measured and the model's terminal voltage against time
(eqs. 3.1-3.3 at the identified parameters, simulated through the recorded current), the current below, the error
(model − measured, mV) below that with the end of the fitted samples marked, and beside them the OCV(z) curve
identified (Fig. 3.4; the discharge branch when the record has no charge).
figure "validate" (`uascma validate battery --plot`): Fig. 3.5: measured and model voltage against time, the error
(mV) below, the summary window shaded, and the End Of Discharge checks (§3.3.2.1): at each fraction of the
discharge, the cut-off time the model predicts from its state there against the recorded one.

Usage: battery_identification.py DATA.json OUT.png
DATA.json: {"figure": "identify" | "validate", "title": str, "time_s": [...], "measured_v": [...],
"model_v": [...], "error_mv": [...] (model − measured),
 identify: "current_a": [...], "fitted_end_s": number (the last fitted sample), "fit_rms_mv", "fit_max_mv",
   "ocv": {"soc_fraction": [...], "voltage_v": [...], "branch": str,
           optional "discharge_branch" and "charge_branch": {"soc_fraction": [...], "voltage_v": [...]}};
 validate: "window": {"begin_s", "end_s"} or null, "voltage_rms_mv", "voltage_max_mv", "cutoff_v",
   "cutoff_time_s": number or null, "eod": [{"at_fraction", "at_time_s", "predicted_s", "actual_s",
   "predicted_cutoff_s" (at_time_s + predicted_s), "relative_error"}]}.
"""

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402

import figure_choice  # noqa: E402

MEASURED = "#212121"
MODEL = "#e53935"
ERROR = "#1565c0"
CURRENT = "#2e7d32"


def outside_legend(ax, **kwargs):
    # Beside the axes, never over the curves.
    ax.legend(loc="upper left", bbox_to_anchor=(1.01, 1.0), borderaxespad=0.0, fontsize=8, **kwargs)


def draw_voltage(ax, data):
    ax.plot(data["time_s"], data["measured_v"], color=MEASURED, linewidth=1.2, label="measured")
    ax.plot(data["time_s"], data["model_v"], color=MODEL, linewidth=1.0, linestyle="--", label="model")
    ax.set_ylabel("terminal voltage (V)")
    ax.grid(alpha=0.3)


def draw_error(ax, data):
    ax.plot(data["time_s"], data["error_mv"], color=ERROR, linewidth=1.0, label="model − measured")
    ax.axhline(0.0, color="#9e9e9e", linewidth=0.8)
    ax.set_ylabel("error (mV)")
    ax.set_xlabel("time (s)")
    ax.grid(alpha=0.3)


def draw_identify(data):
    fig = plt.figure(figsize=(14, 8), layout="constrained")
    grid = fig.add_gridspec(3, 2, width_ratios=(2.2, 1), height_ratios=(2, 1, 1.2))
    voltage = fig.add_subplot(grid[0, 0])
    current = fig.add_subplot(grid[1, 0], sharex=voltage)
    error = fig.add_subplot(grid[2, 0], sharex=voltage)
    draw_voltage(voltage, data)
    voltage.set_title(f"fit: RMS {data['fit_rms_mv']:.2f} mV, max {data['fit_max_mv']:.2f} mV over the fitted samples")
    current.plot(data["time_s"], data["current_a"], color=CURRENT, linewidth=1.0, label="current")
    current.set_ylabel("current (A,\ndischarge > 0)")
    current.grid(alpha=0.3)
    draw_error(error, data)
    for ax in (voltage, current, error):
        ax.axvline(data["fitted_end_s"], color="#757575", linestyle=":", linewidth=1.0,
                   label="end of the fitted samples" if ax is voltage else None)
        if ax is not error:
            ax.tick_params(labelbottom=False)
    outside_legend(voltage)
    outside_legend(current)
    outside_legend(error)
    ocv = fig.add_subplot(grid[:, 1])
    ocv.plot(data["ocv"]["soc_fraction"], data["ocv"]["voltage_v"], "o-", color=MODEL, markersize=3, linewidth=1.2,
             label="OCV(z)")
    for key, style, name in (("discharge_branch", ":", "discharge branch"), ("charge_branch", "--", "charge branch")):
        if key in data["ocv"]:
            branch = data["ocv"][key]
            ocv.plot(branch["soc_fraction"], branch["voltage_v"], style, color=MEASURED, linewidth=1.0, label=name)
    if "charge_branch" in data["ocv"]:
        ocv.legend(fontsize=8, loc="lower right")
    ocv.set_xlabel("state of charge z")
    ocv.set_ylabel("open-circuit voltage (V)")
    ocv.set_title(f"OCV(z) identified\n({data['ocv']['branch']})", fontsize=10)
    ocv.grid(alpha=0.3)
    fig.suptitle(data["title"])
    return fig


def draw_eod_checks(ax, data):
    checks = data["eod"]
    if not checks:
        ax.text(0.5, 0.5, f"the record never reaches\nthe {data['cutoff_v']:g} V cut-off:\nno EOD check",
                ha="center", va="center", transform=ax.transAxes)
        ax.set_axis_off()
        return
    positions = range(len(checks))
    width = 0.38
    predicted = [c["predicted_s"] for c in checks]
    actual = [c["actual_s"] for c in checks]
    ax.bar([p - width / 2 for p in positions], predicted, width, color=MODEL, label="predicted (model)")
    ax.bar([p + width / 2 for p in positions], actual, width, color=MEASURED, label="actual (record)")
    ax.set_xticks(list(positions))
    ax.set_xticklabels([f"{100 * c['at_fraction']:.0f} %\n({100 * c['relative_error']:+.1f} %)" for c in checks])
    ax.set_xlabel("check at this share of the discharge\n(predicted − actual, relative)")
    ax.set_ylabel(f"time to the {data['cutoff_v']:g} V cut-off (s)")
    ax.set_title("End Of Discharge checks (§3.3.2.1)", fontsize=10)
    ax.set_ylim(0.0, 1.25 * max(predicted + actual))
    ax.legend(loc="upper right", fontsize=8)
    ax.grid(alpha=0.3, axis="y")


def draw_validate(data):
    fig = plt.figure(figsize=(14, 7), layout="constrained")
    grid = fig.add_gridspec(2, 2, width_ratios=(2.2, 1), height_ratios=(2, 1))
    voltage = fig.add_subplot(grid[0, 0])
    error = fig.add_subplot(grid[1, 0], sharex=voltage)
    draw_voltage(voltage, data)
    draw_error(error, data)
    voltage.tick_params(labelbottom=False)
    window = data["window"]
    if window is not None:
        for ax in (voltage, error):
            ax.axvspan(window["begin_s"], window["end_s"], color="#fff59d", alpha=0.5, zorder=0,
                       label="summary window" if ax is voltage else None)
    voltage.axhline(data["cutoff_v"], color="#757575", linestyle=":", linewidth=1.0,
                    label=f"cut-off {data['cutoff_v']:g} V")
    for k, check in enumerate(data["eod"]):
        voltage.axvline(check["at_time_s"], color="#6a1b9a", linewidth=0.8, linestyle="-.",
                        label="EOD checks (25/50/75 %)" if k == 0 else None)
        voltage.plot([check["predicted_cutoff_s"]], [data["cutoff_v"]], "v", color=MODEL, markersize=7,
                     label="predicted cut-off" if k == 0 else None)
    if data["cutoff_time_s"] is not None:
        voltage.plot([data["cutoff_time_s"]], [data["cutoff_v"]], "^", color=MEASURED, markersize=7,
                     label="recorded cut-off")
    voltage.set_title(f"voltage error RMS {data['voltage_rms_mv']:.2f} mV, max {data['voltage_max_mv']:.2f} mV "
                      "over the window")
    outside_legend(voltage)
    outside_legend(error)
    draw_eod_checks(fig.add_subplot(grid[:, 1]), data)
    fig.suptitle(data["title"])
    return fig


if __name__ == "__main__":
    figure_choice.run(__doc__, {"identify": draw_identify, "validate": draw_validate})
