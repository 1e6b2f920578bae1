#!/usr/bin/python3
"""Draws the statistics of a Monte Carlo campaign as Figs. 5.30-5.32 of the dissertation do: bars per
battery health (G, M, P) and policy. Rates carry their 95 % Wilson interval as error bars (the SEM of
Figs. 5.30-5.31 is 0 +- 0 at 0 % or 100 %, the Wilson interval is not); rewards carry the SEM. Every bar is
labelled with its n (flights), and the failure-rate plot prints McNemar's paired p-value per health group.

Usage: campaign_report.py REPORT.json OUT_DIR
REPORT.json is `uascma report DB --json`. Writes into OUT_DIR:
  failure_rate.png      Fig. 5.30  failure rate, 95 % Wilson interval, n per bar, McNemar p per group
  completion_rate.png   Fig. 5.31  original flight plan completion rate, 95 % Wilson interval
  rewards.png           Fig. 5.32  average reward per time step and minimum instantaneous reward +- SEM
  outcomes.png          every outcome rate (failure, completion, emergency landing, termination, grounded)
  failure_causes.png    failures by cause (battery, loss of control, collision, timeout, other), stacked
  failure_fades.png     failure rate by the fades the battery carries (a capacity-faded cell, power fade only,
                        none), all health groups, 95 % Wilson interval, n per bar
"""
import json
import math
import os
import sys
import textwrap

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402

HEALTHS = ["G", "M", "P"]
HEALTH_LABELS = {"G": "Good", "M": "Medium", "P": "Poor"}
COLOURS = ["#1f77b4", "#d62728", "#2ca02c", "#9467bd", "#ff7f0e", "#8c564b"]
CAUSES = [("battery", "battery"), ("loss_of_control", "loss of control"), ("collision", "collision"),
          ("timeout", "timeout"), ("other", "other")]
CAUSE_COLOURS = ["#ff7f0e", "#9467bd", "#8c564b", "#7f7f7f", "#bcbd22"]
FADES = [("none", "no fade"), ("power_only", "power fade only\n(2 R0)"), ("capacity", "a capacity-faded cell\n(0.8 Q)")]


def value(group, key):
    v = group.get(key)
    return float("nan") if v is None else v


def offsets(count):
    width = 0.8 / max(1, count)
    return width, [(i - (count - 1) / 2) * width for i in range(count)]


def n_label(ax, x, y, low, high, n, vertical=False):
    """'n=…' beyond the end of the bar's error bar (its cap): above a positive bar, below a negative one, so the
    label never sits on the interval or the bar."""
    low = 0.0 if math.isnan(low) else low
    high = 0.0 if math.isnan(high) else high
    if math.isnan(y) or y >= 0:
        end, offset, va = (0.0 if math.isnan(y) else y + high), 3, "bottom"
    else:
        end, offset, va = y - low, -3, "top"
    ax.annotate(f"n={n}", (x, end), xytext=(0, offset), textcoords="offset points", ha="center", va=va, fontsize=8,
                rotation=90 if vertical else 0)


def headroom(ax, fraction=0.18):
    """Room beyond the longest bars (above, and below negative ones) for the labels there."""
    ax.autoscale_view()  # from the data (of every axes sharing y): repeated calls do not compound
    low, high = ax.get_ylim()
    span = high - low
    ax.set_ylim(low - (fraction * span if low < 0 else 0.0), high + fraction * span)


def bars(ax, report, key, scale=1.0, ylabel=""):
    """Bars of `key` per health and policy; Wilson error bars when the report has them, else the SEM."""
    policies = report["policy_order"]
    width, shift = offsets(len(policies))
    for i, policy in enumerate(policies):
        groups = report["policies"][policy]
        xs = [h + shift[i] for h in range(len(HEALTHS))]
        ys = [scale * value(groups[h], key) for h in HEALTHS]
        if key + "_wilson_low" in groups[HEALTHS[0]]:
            lows = [scale * value(groups[h], key + "_wilson_low") for h in HEALTHS]
            highs = [scale * value(groups[h], key + "_wilson_high") for h in HEALTHS]
            errors = [[0 if math.isnan(y) else y - lo for y, lo in zip(ys, lows)],
                      [0 if math.isnan(y) else hi - y for y, hi in zip(ys, highs)]]
        else:
            sem = [scale * value(groups[h], key + "_sem") for h in HEALTHS]
            errors = [sem, sem]
        ax.bar(xs, ys, width, yerr=errors, capsize=4, color=COLOURS[i % len(COLOURS)],
               label=f"{policy} (n={sum(groups[h]['runs'] for h in HEALTHS)})")
        for x, y, low, high, h in zip(xs, ys, errors[0], errors[1], HEALTHS):
            n_label(ax, x, y, low, high, groups[h]["runs"], vertical=len(policies) > 3)
    ax.set_xticks(range(len(HEALTHS)))
    ax.set_xticklabels([HEALTH_LABELS[h] for h in HEALTHS])
    ax.set_xlabel("battery health")
    ax.set_ylabel(ylabel)
    ax.grid(axis="y", alpha=0.3)
    headroom(ax)
    legend_outside(ax)


def annotate_mcnemar(ax, report):
    """McNemar's exact p of the first pair of policies above each health group."""
    comparisons = report.get("paired_comparisons") or []
    if not comparisons:
        return
    first = comparisons[0]["policies"]
    top = ax.get_ylim()[1]
    for h_index, h in enumerate(HEALTHS):
        for c in comparisons:
            if c["policies"] == first and c["battery_health"] == h and c["pairs"] > 0:
                p = c["mcnemar_exact_p"]
                ax.text(h_index, 0.82 * top, f"McNemar p={p:.2g}\nb={c['only_first_failed']}, "
                        f"c={c['only_second_failed']}", ha="center", va="top", fontsize=8)
    # Under the axis, not in the plot where it would cross the bars' intervals.
    ax.set_xlabel(f"{ax.get_xlabel()}\n(McNemar: {first[0]} vs {first[1]}, paired on the same flights)")


def cause_bars(ax, report):
    """Failures by cause as stacked bars (percent of the group's flights), per health and policy."""
    policies = report["policy_order"]
    width, shift = offsets(len(policies))
    for i, policy in enumerate(policies):
        groups = report["policies"][policy]
        xs = [h + shift[i] for h in range(len(HEALTHS))]
        bottom = [0.0] * len(HEALTHS)
        for c, (cause, label) in enumerate(CAUSES):
            ys = []
            for h in HEALTHS:
                runs = groups[h]["runs"]
                count = groups[h].get("failures_by_cause", {}).get(cause, 0)
                ys.append(100.0 * count / runs if runs else 0.0)
            ax.bar(xs, ys, width, bottom=bottom, color=CAUSE_COLOURS[c], edgecolor="white",
                   label=label if i == 0 else None)
            bottom = [b + y for b, y in zip(bottom, ys)]
        for x, top, h in zip(xs, bottom, HEALTHS):
            ax.annotate(f"{policy}\nn={groups[h]['runs']}", (x, top), xytext=(0, 2), textcoords="offset points",
                        ha="center", va="bottom", fontsize=8)
    ax.set_xticks(range(len(HEALTHS)))
    ax.set_xticklabels([HEALTH_LABELS[h] for h in HEALTHS])
    ax.set_xlabel("battery health")
    ax.set_ylabel("failures (% of flights)")
    ax.grid(axis="y", alpha=0.3)
    headroom(ax, 0.3)
    legend_outside(ax, title="cause")


def wilson(failures, runs, z=1.959963984540054):
    """The 95 % Wilson score interval of failures / runs, as fractions (nan, nan) without runs."""
    if runs == 0:
        return float("nan"), float("nan")
    p = failures / runs
    denominator = 1 + z * z / runs
    centre = (p + z * z / (2 * runs)) / denominator
    half = z * math.sqrt(p * (1 - p) / runs + z * z / (4 * runs * runs)) / denominator
    return max(0.0, centre - half), min(1.0, centre + half)


def fade_bars(ax, report):
    """Failure rate per fade class of the battery (all health groups), per policy, with Wilson intervals."""
    policies = report["policy_order"]
    width, shift = offsets(len(policies))
    for i, policy in enumerate(policies):
        fades = report["policies"][policy]["all"].get("by_battery_fades", {})
        xs = [f + shift[i] for f in range(len(FADES))]
        ys, lows, highs, ns = [], [], [], []
        for key, _ in FADES:
            entry = fades.get(key, {"runs": 0, "failures": 0})
            runs, failures = entry["runs"], entry["failures"]
            low, high = wilson(failures, runs)
            y = 100.0 * failures / runs if runs else float("nan")
            ys.append(y)
            lows.append(0 if math.isnan(y) else max(0.0, y - 100.0 * low))
            highs.append(0 if math.isnan(y) else max(0.0, 100.0 * high - y))
            ns.append(runs)
        ax.bar(xs, ys, width, yerr=[lows, highs], capsize=4, color=COLOURS[i % len(COLOURS)], label=policy)
        for x, y, low, high, n in zip(xs, ys, lows, highs, ns):
            n_label(ax, x, y, low, high, n)
    ax.set_xticks(range(len(FADES)))
    ax.set_xticklabels([label for _, label in FADES])
    ax.set_xlabel("the fades the battery carries (Table 3.2)")
    ax.set_ylabel("failure rate (%)")
    ax.grid(axis="y", alpha=0.3)
    headroom(ax)
    legend_outside(ax)


def legend_outside(ax, **kwargs):
    """The legend to the right of the axes: never over the bars."""
    return ax.legend(loc="upper left", bbox_to_anchor=(1.01, 1.0), borderaxespad=0.0, fontsize=8, **kwargs)


def set_title(ax, head, name):
    """The figure's title: `head`, then the campaign's name on lines of its own, wrapped to the axes' width (a
    long name on one line ran off the figure's edge)."""
    fig = ax.get_figure()
    size_pt = matplotlib.rcParams["axes.titlesize"]
    size_pt = size_pt if isinstance(size_pt, (int, float)) else matplotlib.font_manager.FontProperties(
        size=size_pt).get_size_in_points()
    # Characters per line: the axes' width over a character's mean advance, ~0.6 em (ours, for DejaVu Sans).
    width_pt = fig.get_figwidth() * ax.get_position().width * 72.0
    chars = max(20, int(width_pt / (0.6 * size_pt)))
    lines = textwrap.wrap(head, chars) + textwrap.wrap(name, chars, break_long_words=True)
    ax.set_title("\n".join(lines))


def save(fig, out_dir, name):
    fig.tight_layout()
    fig.savefig(os.path.join(out_dir, name), dpi=120)
    plt.close(fig)


def main(source, out_dir):
    with open(source) as f:
        report = json.load(f)
    os.makedirs(out_dir, exist_ok=True)
    title = report["campaign"]["name"]
    level = round(100 * report.get("confidence_level", 0.95))

    fig, ax = plt.subplots(figsize=(7, 5))
    bars(ax, report, "failure_rate", 100.0, "failure rate (%)")
    ax.set_ylim(0, max(ax.get_ylim()[1], 10) * 1.45)
    annotate_mcnemar(ax, report)
    set_title(ax, f"Failure rate, {level} % Wilson interval (cf. Fig. 5.30)", title)
    save(fig, out_dir, "failure_rate.png")

    fig, ax = plt.subplots(figsize=(7, 5))
    bars(ax, report, "completion_rate", 100.0, "original plan completed (%)")
    set_title(ax, f"Original flight plan completion, {level} % Wilson (cf. Fig. 5.31)", title)
    save(fig, out_dir, "completion_rate.png")

    fig, axes = plt.subplots(1, 2, figsize=(12, 4.5))
    bars(axes[0], report, "average_reward", 1.0, "average reward per time step")
    axes[0].set_title("Average reward ± SEM (cf. Fig. 5.32)")
    bars(axes[1], report, "min_reward", 1.0, "minimum instantaneous reward")
    axes[1].set_title("Minimum instantaneous reward ± SEM (cf. Fig. 5.32)")
    save(fig, out_dir, "rewards.png")

    keys = [("failure_rate", "failure"), ("completion_rate", "completed"),
            ("emergency_landing_rate", "emergency landing"), ("termination_rate", "terminated"),
            ("grounded_rate", "grounded")]
    keys = [k for k in keys if k[0] in report["policies"][report["policy_order"][0]]["all"]]
    # At most three panels a row: five in one row made a 22.5-inch figure whose text, shown page-wide, was ~7 px.
    columns = min(3, len(keys))
    rows = math.ceil(len(keys) / columns)
    fig, axes = plt.subplots(rows, columns, figsize=(4.5 * columns, 4.5 * rows), sharey=True, squeeze=False)
    for ax, (key, label) in zip(axes.flat, keys):
        bars(ax, report, key, 100.0, "rate (%)")
        ax.set_title(label)
    for ax in list(axes.flat)[len(keys):]:
        ax.set_visible(False)
    save(fig, out_dir, "outcomes.png")

    fig, ax = plt.subplots(figsize=(7, 5))
    cause_bars(ax, report)
    ax.set_ylim(0, max(ax.get_ylim()[1], 5) * 1.2)
    set_title(ax, "Failures by cause", title)
    save(fig, out_dir, "failure_causes.png")

    if "by_battery_fades" in report["policies"][report["policy_order"][0]]["all"]:
        fig, ax = plt.subplots(figsize=(7, 5))
        fade_bars(ax, report)
        ax.set_ylim(0, max(ax.get_ylim()[1], 5) * 1.2)
        set_title(ax, f"Failure rate by the battery's fades, {level} % Wilson", title)
        save(fig, out_dir, "failure_fades.png")


if __name__ == "__main__":
    if len(sys.argv) != 3:
        sys.exit(__doc__)
    main(sys.argv[1], sys.argv[2])
