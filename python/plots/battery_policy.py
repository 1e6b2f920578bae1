#!/usr/bin/python3
"""Draws the battery-reconfiguration policies as the decision tree of dissertation Fig. 4.5 (§4.3.2.1).

Usage: battery_policy.py VIEW.json OUT.png
VIEW.json is `uascma battery show POLICY --json`: per context (B1F, B2F, T) the action of each of the 289
states, whether that choice's row was ever observed, and the state the context's case-study flight takes off in
(that flight's length: docs/modelling-choices.md#battery-case-study-flight-time).

Left panel, the tree: B1 health (F1/F2/F3) -> B2 health -> temperature class (TL/TH) down to one policy pi* per
context (18 leaves, §4.3.2.1: "the policies are selected traversing the appropriate tree branch"). Each leaf shows
the action its policy takes at the take-off state; a dashed leaf with "*" means that choice's row was never observed
in the learning flights (the model then lets that state loop on itself,
docs/modelling-choices.md#battery-mdp-transitions). Right panel, aligned with the leaves: how
many of the 72 states with both packs in each action is chosen in (where every policy chooses; ours holds its
switches in a one-pack state by construction), the never-observed choices hatched. A key below explains every code (Tables 4.1-4.3).
"""
import json
import sys

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402
from matplotlib.patches import Patch  # noqa: E402

ACTIONS = ["UseBatt1", "UseBatt2", "UseBoth"]
COLOURS = ["#90caf9", "#ffcc80", "#a5d6a7"]  # light fills: black text on them stays readable
HEALTH = ["F1", "F2", "F3"]
TEMPERATURES = ["TL", "TH"]
FONT = 10          # pt; 13.9 px at the saved 100 dpi, above the 8 px floor of tests/python/test_plots.py
DPI = 100

KEY = [
    "Tree (Fig. 4.5): B1 / B2 = health of pack 1 / pack 2 (Table 4.2): F1 healthy, F2 medium (power or capacity fade "
    "in a cell), F3 unhealthy (power and capacity fade); temperature (Table 4.2): TL below 50 F, TH above 50 F.",
    "Leaf: the action {policy} takes at the take-off state, the first state of the context's {flight:.0f} s case-study "
    "flight. Actions (Table 4.3): UseBatt1 = Sw1 ON, Sw2 OFF; UseBatt2 = Sw1 OFF, Sw2 ON; "
    "UseBoth = both ON.",
    "* and dashed leaf, hatched bar: the chosen action's row was never observed in the learning flights; the model "
    "lets that state loop on itself (p = 1), so the choice rests on no data.",
    "State code (Table 4.1): current IL / IH (below / above 0.2 Imax), then pack 1 and pack 2 each as switch ON / OFF, "
    "energy S1 / S2 / S3 and voltage C0 / C1, e.g. ILONS3C0ONS3C0.",
    "S1: EOD > RFD + tsf;  S2: RFD <= EOD <= RFD + tsf;  S3: EOD < RFD  (EOD end of discharge, RFD remaining flight "
    "duration, tsf safety margin);  C0: worst cell >= 3.4 V, C1: below 3.4 V.",
]


def leaves(view):
    """The 18 contexts in tree order (B1, then B2, then T), whatever order the file lists them in."""
    by_key = {(c["b1"], c["b2"], c["temperature"]): c for c in view["contexts"]}
    ordered = []
    for b1 in HEALTH:
        for b2 in HEALTH:
            for t in TEMPERATURES:
                if (b1, b2, t) not in by_key:
                    raise SystemExit(f"battery_policy.py: the view has no context {b1},{b2},{t}")
                ordered.append(by_key[(b1, b2, t)])
    return ordered


def node(ax, x, y, text, **style):
    box = dict(boxstyle="round,pad=0.35", facecolor="white", edgecolor="black", linewidth=1.0)
    box.update(style.pop("box", {}))
    return ax.text(x, y, text, ha="center", va="center", fontsize=FONT, bbox=box, zorder=3, **style)


def box_sides(ax, text):
    """The left and right ends (data x) of a node's drawn box, so that edges meet the boxes."""
    renderer = ax.figure.canvas.get_renderer()
    extent = text.get_bbox_patch().get_window_extent(renderer)
    (x0, _), (x1, _) = ax.transData.inverted().transform([(extent.x0, 0.0), (extent.x1, 0.0)])
    return x0, x1


def edge(ax, parent, child):
    """An elbow from a parent's right side to a child's left side (no markers: the layout check ignores it)."""
    (_, x0), y0 = box_sides(ax, parent), parent.get_position()[1]
    (x1, _), y1 = box_sides(ax, child), child.get_position()[1]
    mid = x0 + 0.5 * (x1 - x0)
    ax.plot([x0, mid, mid, x1], [y0, y0, y1, y1], color="grey", linewidth=1.0, zorder=1)


def policy_name(view):
    """The policy the view draws: the dissertation's pi*, or ours' table (its guard and drop check act outside it,
    docs/battery.md)."""
    return "\u03c0*" if view.get("formulation", "dissertation") == "dissertation" else "ours' table"


def root_label(view):
    """The tree's root: what is looked up (pi*'s solved tables, or ours' table without its guard and drop check)."""
    if view.get("formulation", "dissertation") == "dissertation":
        return "\u03c0* lookup\n(18 leaves)"
    return "ours' table lookup\n(guard and drop\ncheck outside it;\n18 leaves)"


def draw_tree(ax, contexts, view):
    # x positions of the levels (data units); leaves at y = 0..17 top to bottom.
    x_root, x_b1, x_b2, x_t, x_leaf = 0.0, 1.2, 2.4, 3.5, 4.6
    ys = list(range(len(contexts)))
    header_y = -1.3
    for x, label in [(x_b1, "B1 health"), (x_b2, "B2 health"), (x_t, "temperature"),
                     (x_leaf, "action at take-off")]:
        ax.text(x, header_y, label, ha="center", va="center", fontsize=FONT, fontweight="bold")
    ax.set_xlim(-0.6, 5.5)
    ax.set_ylim(len(contexts) - 0.5, header_y - 0.6)
    ax.axis("off")
    links = []  # (parent, child) texts; the edges are drawn once the boxes have their size
    root = node(ax, x_root, (ys[0] + ys[-1]) / 2.0, root_label(view))
    for i, b1 in enumerate(HEALTH):
        b1_ys = ys[i * 6:(i + 1) * 6]
        b1_node = node(ax, x_b1, sum(b1_ys) / 6.0, f"B1 {b1}")
        links.append((root, b1_node))
        for j, b2 in enumerate(HEALTH):
            b2_ys = b1_ys[j * 2:(j + 1) * 2]
            b2_node = node(ax, x_b2, sum(b2_ys) / 2.0, f"B2 {b2}")
            links.append((b1_node, b2_node))
            for k, t in enumerate(TEMPERATURES):
                y = b2_ys[k]
                context = contexts[y]
                t_node = node(ax, x_t, y, t)
                action = context["takeoff_action"]
                unobserved = bool(context["takeoff_unobserved"])
                leaf = node(ax, x_leaf, y, f"{action}{' *' if unobserved else ''}",
                            box={"facecolor": COLOURS[ACTIONS.index(action)], "linestyle": "--" if unobserved else "-",
                                 "linewidth": 1.6 if unobserved else 1.0})
                links += [(b2_node, t_node), (t_node, leaf)]
    ax.figure.canvas.draw()
    for parent, child in links:
        edge(ax, parent, child)
    states = sorted({c["takeoff_state"] for c in contexts})
    where = states[0] if len(states) == 1 else "each context's own"
    ax.set_title(f"decision tree (Fig. 4.5); take-off state {where}", fontsize=FONT + 1)


def draw_counts(ax, contexts, view):
    """Per leaf, the states with both packs in (72) in which each action is chosen; never-observed hatched. Only
    there does every policy choose: in a one-pack state ours holds its switches by construction, so counting those
    holds would hide a policy that never leaves UseBoth."""
    both_in = view["both_in"]
    possible = [s for s in range(len(view["states"])) if both_in[s]]
    for y, context in enumerate(contexts):
        left = 0
        for a, action in enumerate(ACTIONS):
            chosen = [s for s in possible if context["action"][s] == action]
            missing = sum(1 for s in chosen if context["unobserved"][s])
            if not chosen:
                continue
            ax.barh(y, len(chosen), left=left, height=0.7, color=COLOURS[a], edgecolor="black", linewidth=0.6)
            if missing:
                ax.barh(y, missing, left=left + len(chosen) - missing, height=0.7, facecolor="none",
                        edgecolor="dimgrey", hatch="///", linewidth=0)
            if len(chosen) >= 8:  # a 2-digit count at FONT fits in 8 of the 72 states' width
                ax.text(left + len(chosen) / 2.0, y, str(len(chosen)), ha="center", va="center", fontsize=FONT - 1)
            left += len(chosen)
    ax.set_xlim(0, len(possible))
    ax.set_ylim(len(contexts) - 0.5, -1.3 - 0.6)
    ax.set_yticks([])
    ax.set_xticks([0, 18, 36, 54, 72])
    ax.tick_params(labelsize=FONT)
    ax.set_xlabel(f"states per action (of the {len(possible)} with both packs in)", fontsize=FONT)
    ax.set_title("choices with both packs in, per leaf", fontsize=FONT + 1)
    for side in ("top", "right", "left"):
        ax.spines[side].set_visible(False)


def draw(view):
    """The figure of a view (`battery show --json`); the tree is fig.axes[0], the counts fig.axes[1]."""
    contexts = leaves(view)
    fig = plt.figure(figsize=(15, 12.5), dpi=DPI)
    grid = fig.add_gridspec(1, 2, width_ratios=[2.1, 1.0], left=0.02, right=0.98, top=0.94, bottom=0.24,
                            wspace=0.04)
    tree = fig.add_subplot(grid[0, 0])
    counts = fig.add_subplot(grid[0, 1])
    draw_tree(tree, contexts, view)
    draw_counts(counts, contexts, view)
    handles = [Patch(facecolor=c, edgecolor="black", label=a) for a, c in zip(ACTIONS, COLOURS)]
    handles.append(Patch(facecolor="white", edgecolor="black", linestyle="--", linewidth=1.6,
                         label="* take-off choice never observed"))
    handles.append(Patch(facecolor="white", edgecolor="dimgrey", hatch="///", label="choices never observed"))
    fig.legend(handles=handles, loc="lower center", bbox_to_anchor=(0.5, 0.165), ncol=5, fontsize=FONT,
               frameon=False)
    flight = view.get("takeoff_flight_s", 0.0)
    for i, line in enumerate(KEY):
        fig.text(0.02, 0.13 - i * 0.024, line.format(flight=flight, policy=policy_name(view)), fontsize=FONT - 1,
                 ha="left", va="top")
    fig.suptitle(f"Battery policies (Fig. 4.5), {view.get('formulation', 'dissertation')} formulation, "
                 f"gamma {view['gamma']:.6g}, model {view['model_hash']}", fontsize=FONT + 2)
    return fig


def main(source, target):
    with open(source) as f:
        view = json.load(f)
    draw(view).savefig(target, dpi=DPI)


if __name__ == "__main__":
    if len(sys.argv) != 3:
        sys.exit("usage: battery_policy.py VIEW.json OUT.png")
    main(sys.argv[1], sys.argv[2])
