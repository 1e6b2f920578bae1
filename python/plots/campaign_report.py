#!/usr/bin/python3
"""Draws the statistics of a Monte Carlo campaign as Figs. 5.30-5.32 of the dissertation do: bars per
battery health (G, M, P) and policy, with the standard error of the mean as error bars.

Usage: campaign_report.py REPORT.json OUT_DIR
REPORT.json is `uascma report DB --json`. Writes into OUT_DIR:
  failure_rate.png      Fig. 5.30  failure rate +- SEM
  completion_rate.png   Fig. 5.31  original flight plan completion rate +- SEM
  rewards.png           Fig. 5.32  average reward per time step and minimum instantaneous reward +- SEM
  outcomes.png          every outcome rate (failure, completion, emergency landing, termination)
"""
import json
import os
import sys

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402

HEALTHS = ["G", "M", "P"]
HEALTH_LABELS = {"G": "Good", "M": "Medium", "P": "Poor"}
COLOURS = ["#1f77b4", "#d62728", "#2ca02c", "#9467bd", "#ff7f0e", "#8c564b"]


def value(group, key):
    v = group.get(key)
    return float("nan") if v is None else v


def bars(ax, report, key, scale=1.0, ylabel=""):
    policies = report["policy_order"]
    width = 0.8 / max(1, len(policies))
    for i, policy in enumerate(policies):
        groups = report["policies"][policy]
        xs = [h + (i - (len(policies) - 1) / 2) * width for h in range(len(HEALTHS))]
        ys = [scale * value(groups[h], key) for h in HEALTHS]
        es = [scale * value(groups[h], key + "_sem") for h in HEALTHS]
        ax.bar(xs, ys, width, yerr=es, capsize=4, color=COLOURS[i % len(COLOURS)],
               label=f"{policy} (n={sum(groups[h]['runs'] for h in HEALTHS)})")
    ax.set_xticks(range(len(HEALTHS)))
    ax.set_xticklabels([HEALTH_LABELS[h] for h in HEALTHS])
    ax.set_xlabel("battery health")
    ax.set_ylabel(ylabel)
    ax.grid(axis="y", alpha=0.3)
    ax.legend()


def save(fig, out_dir, name):
    fig.tight_layout()
    fig.savefig(os.path.join(out_dir, name), dpi=120)
    plt.close(fig)


def main(source, out_dir):
    with open(source) as f:
        report = json.load(f)
    os.makedirs(out_dir, exist_ok=True)
    title = report["campaign"]["name"]

    fig, ax = plt.subplots(figsize=(6.5, 4.5))
    bars(ax, report, "failure_rate", 100.0, "failure rate (%)")
    ax.set_title(f"Failure rate ± SEM (cf. Fig. 5.30) — {title}")
    save(fig, out_dir, "failure_rate.png")

    fig, ax = plt.subplots(figsize=(6.5, 4.5))
    bars(ax, report, "completion_rate", 100.0, "original plan completed (%)")
    ax.set_title(f"Original flight plan completion ± SEM (cf. Fig. 5.31) — {title}")
    save(fig, out_dir, "completion_rate.png")

    fig, axes = plt.subplots(1, 2, figsize=(12, 4.5))
    bars(axes[0], report, "average_reward", 1.0, "average reward per time step")
    axes[0].set_title("Average reward ± SEM (cf. Fig. 5.32)")
    bars(axes[1], report, "min_reward", 1.0, "minimum instantaneous reward")
    axes[1].set_title("Minimum instantaneous reward ± SEM (cf. Fig. 5.32)")
    save(fig, out_dir, "rewards.png")

    keys = [("failure_rate", "failure"), ("completion_rate", "completed"),
            ("emergency_landing_rate", "emergency landing"), ("termination_rate", "terminated")]
    fig, axes = plt.subplots(1, len(keys), figsize=(18, 4.5), sharey=True)
    for ax, (key, label) in zip(axes, keys):
        bars(ax, report, key, 100.0, "rate (%)")
        ax.set_title(label)
    save(fig, out_dir, "outcomes.png")


if __name__ == "__main__":
    if len(sys.argv) != 3:
        sys.exit(__doc__)
    main(sys.argv[1], sys.argv[2])
