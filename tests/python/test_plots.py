"""Every picture the command-line tool draws is rendered and checked with matplotlib's own extents:
no two texts overlap (the "jam" and "isolated" labels of a jam and its isolation seconds apart included), no
legend covers data, no label sits on data (the report's n= labels on error bars), no text is too small to read.

The check (tests/python/layout_check/sitecustomize.py) wraps Figure.savefig in the plotting interpreter the CLI
starts, so the figures checked are exactly those written."""
import json
import os

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402
import pytest  # noqa: E402

from conftest import SOURCE_DIR, example, run_cli  # noqa: E402

CHECK_DIR = os.path.join(os.path.dirname(os.path.abspath(__file__)), "layout_check")


@pytest.fixture
def checked(monkeypatch, tmp_path):
    """Runs CLI commands with the layout check on; returns (run, figures) where figures() reads the report."""
    report = tmp_path / "layout.jsonl"
    monkeypatch.setenv("PYTHONPATH", CHECK_DIR + os.pathsep + os.environ.get("PYTHONPATH", ""))
    monkeypatch.setenv("UASCMA_LAYOUT_REPORT", str(report))

    def figures():
        if not report.exists():
            return []
        with open(report) as f:
            return [json.loads(line) for line in f]

    return run_cli, figures


def assert_clean(figures, expected):
    written = [f["file"] for f in figures]
    assert sorted(written) == sorted(expected)
    problems = {f["file"]: f["problems"] for f in figures if f["problems"]}
    assert problems == {}


def test_the_checker_finds_overlaps_covered_data_and_small_text():
    import sys

    sys.path.insert(0, CHECK_DIR)
    try:
        from layout import check
    finally:
        sys.path.remove(CHECK_DIR)
    fig, ax = plt.subplots()
    ax.plot(range(100), [0.5] * 100, "o", label="data")
    ax.text(10, 0.6, "jam", fontsize=9)
    ax.text(11, 0.6, "isolated", fontsize=9)  # one second later: the same place on the page
    ax.legend(loc="center")  # over the points
    ax.set_xlabel("time (s)", fontsize=4)
    problems = check(fig)
    plt.close(fig)
    assert any("'jam' and 'isolated'" in p for p in problems)
    assert any("legend" in p and "covers" in p for p in problems)
    assert any("'time (s)'" in p and "px high" in p for p in problems)


def test_the_checker_finds_what_the_figure_edge_cuts():
    import sys

    sys.path.insert(0, CHECK_DIR)
    try:
        from layout import check
    finally:
        sys.path.remove(CHECK_DIR)
    # A legend placed right of the axes (map.png's) and a centred title longer than the figure is wide
    # (completion_rate.png's with a long campaign name).
    fig, ax = plt.subplots(figsize=(4, 3))
    ax.plot([0, 1], [0, 1], label="a route with a long name")
    ax.legend(loc="upper left", bbox_to_anchor=(1.0, 1.0))
    ax.set_title("completion rate of campaign " + "a-long-campaign-name-" * 4)
    problems = check(fig)
    assert any("legend is cut" in p for p in problems), problems
    assert any("completion rate of campaign" in p and "cut at the figure's edge" in p for p in problems), problems
    # The same figure saved with bbox_inches="tight" grows to hold both.
    assert not any("cut at the figure's edge" in p or "legend is cut" in p for p in check(fig, tight=True))
    plt.close(fig)
    # Laid out inside the figure: nothing is cut.
    fig, ax = plt.subplots(figsize=(4, 3), layout="constrained")
    ax.plot([0, 1], [0, 1], label="a route")
    ax.legend(loc="lower right")
    ax.set_title("completion rate")
    assert check(fig) == []
    plt.close(fig)


def test_flight_plots_over_a_city_with_a_jam(checked, tmp_path):
    run, figures = checked
    # Scenario I (§5.5.1): motor 3 spalls, jams and is isolated seconds later; LandPract over the city.
    run("simulate", example("scenario-1.yaml"), "--out", tmp_path / "s1")
    run("plot", tmp_path / "s1")
    assert_clean(figures(), ["path.png", "states.png", "forces.png", "rotors.png", "battery.png", "eod.png",
                             "decisions.png", "map.png"])


def test_flight_plots_on_open_ground(checked, tmp_path):
    run, figures = checked
    run("simulate", example("jam-motor-3.yaml"), "--out", tmp_path / "jam")
    run("plot", tmp_path / "jam")
    assert_clean(figures(), ["path.png", "states.png", "forces.png", "rotors.png", "battery.png", "eod.png",
                             "decisions.png"])


def test_report_plots(checked, tmp_path):
    run, figures = checked
    # A long campaign name: the titles that carry it stay inside their figures.
    with open(example("campaign.yaml")) as f:
        text = f.read().replace("name: dissertation-5.5", "name: " + "a-campaign-with-a-long-descriptive-name-" * 3)
    config = tmp_path / "campaign.yaml"
    config.write_text(text)
    run("campaign", config, "--runs", 30, "--seed", 5, "--db", tmp_path / "c.db")
    run("report", tmp_path / "c.db", "--plots", tmp_path / "plots")
    written = [f["file"] for f in figures()]
    assert "failure_rate.png" in written and "failure_causes.png" in written
    assert_clean(figures(), written)


def test_policy_footprint_and_map_plots(checked, tmp_path):
    run, figures = checked
    run("policy", "solve", "--model", "cma", "--out", tmp_path / "policy.json")
    run("policy", "show", tmp_path / "policy.json", "--plot", tmp_path / "policy.png")
    run("footprint", "--speed-mps", 5, "--eod-s", 300, "--plot", tmp_path / "footprint.png")
    run("map", "info", "--plot", tmp_path / "map.png")
    run("learn", "q", "--episodes", 20, "--out", tmp_path / "q.json", "--plot", tmp_path / "curve.png")
    assert_clean(figures(), ["policy.png", "footprint.png", "map.png", "curve.png"])


@pytest.fixture
def battery_policy(cli, tmp_path):
    """A battery policy from a small learning run (60 flights, seed 1: seconds), and `battery show`'s text table."""
    run_cli("battery", "learn", "--runs", 60, "--seed", 1, "--out", tmp_path / "m.json")
    run_cli("battery", "solve", tmp_path / "m.json", "--out", tmp_path / "p.json")
    return tmp_path / "p.json"


def test_battery_policy_plot_is_clean(checked, battery_policy, tmp_path):
    run, figures = checked
    run("battery", "show", battery_policy, "--plot", tmp_path / "battery-policy.png")
    assert (tmp_path / "battery-policy.png").stat().st_size > 0
    # The CLI draws beside the target and renames over it (".uascma-plot-PID-NAME"): the check sees that name.
    drawn = [dict(f, file=f["file"].split("-", 3)[-1] if f["file"].startswith(".uascma-plot-") else f["file"])
             for f in figures()]
    assert_clean(drawn, ["battery-policy.png"])


def test_battery_policy_tree_shows_what_battery_show_prints(battery_policy):
    # Fig. 4.5's tree (B1 health -> B2 health -> temperature -> one policy) drawn from `battery show --json` must
    # carry, leaf by leaf, what the C++ text table prints: the take-off action with its "*" (row never observed),
    # the states per action and the never-observed choices (the bars of the second panel; widths in states).
    import importlib.util
    import re

    spec = importlib.util.spec_from_file_location(
        "battery_policy", os.path.join(SOURCE_DIR, "python", "plots", "battery_policy.py"))
    module = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(module)
    table = {}
    for line in run_cli("battery", "show", battery_policy).stdout.splitlines():
        m = re.match(r"^(T[LH])\s+(F\d)\s+(F\d)\s+(\d+)\s+(\d+)\s+(\d+)\s+\d+\s+(\d+) of 72\s+\S+\s+(\w+)( \*)?$",
                     line)
        if m:
            t, b1, b2, n1, n2, nb, missing, action, star = m.groups()
            table[(b1, b2, t)] = (f"{action}{star or ''}", [int(n1), int(n2), int(nb)], int(missing))
    assert len(table) == 18
    fig = module.draw(json.loads(run_cli("battery", "show", battery_policy, "--json").stdout))
    tree, counts = fig.axes
    texts = [(t.get_text(), t.get_position()) for t in tree.texts]
    leaves = sorted((y, s) for s, (x, y) in texts if s.startswith("Use"))
    temperatures = {y: s for s, (x, y) in texts if s in ("TL", "TH")}
    order = [(b1, b2, t) for b1 in ("F1", "F2", "F3") for b2 in ("F1", "F2", "F3") for t in ("TL", "TH")]
    assert [s for _, s in leaves] == [table[key][0] for key in order]
    assert [temperatures[y] for y, _ in leaves] == [key[2] for key in order]
    for row, key in enumerate(order):
        bars = [p for p in counts.patches if abs(p.get_y() + p.get_height() / 2 - row) < 1e-9]
        chosen = [round(p.get_width()) for p in bars if not p.get_hatch()]
        hatched = sum(round(p.get_width()) for p in bars if p.get_hatch())
        assert [n for n in table[key][1] if n] == chosen, key
        assert hatched == table[key][2], key
    plt.close(fig)


def test_grounded_flight_prints_no_infinite_cell_voltage(cli, tmp_path):
    # A policy that lands (LandASAP) in every N state grounds the flight before take-off: no step is flown, so
    # there is no cell minimum nor a real-time factor to print (they were "inf V" and "0x real time").
    run_cli("policy", "solve", "--model", "cma", "--out", tmp_path / "cma.json")
    policy = json.loads((tmp_path / "cma.json").read_text())
    for entry in policy["states"]:
        if entry["state"].startswith("N,"):
            entry["action"] = "LandASAP"
    (tmp_path / "land.json").write_text(json.dumps(policy))
    out = run_cli("simulate", example("scenario-1.yaml"), "--policy", tmp_path / "land.json").stdout
    assert out.startswith("scenario-1: grounded")
    assert "inf" not in out and "real time" not in out and "stayed on the ground" in out


def test_identification_plots(checked, tmp_path):
    # The figures of docs/identification.md: the cell fit and its validation (Fig. 3.5), the pair's fit (Fig. 2.10)
    # and its validation (Fig. 2.11), a drag table; the data of examples/identify/run.sh.
    run, figures = checked
    nasa = os.path.join(SOURCE_DIR, "data", "bench", "battery-nasa", "B0005.csv")
    stand = os.path.join(SOURCE_DIR, "data", "bench", "dyno-strawson")
    run("identify", "battery", nasa, "--cycle", 1, "--out", tmp_path / "cell.json", "--plot", tmp_path / "cell.png")
    run("validate", "battery", "--model", tmp_path / "cell.json", nasa, "--cycle", 2, "--window-low-v", 3.0,
        "--window-high-v", 4.1, "--plot", tmp_path / "cell-validation.png")
    run("identify", "propulsion", os.path.join(stand, "g8_7.csv"), os.path.join(stand, "g8_11.csv"),
        "--pole-pairs", 1, "--diameter-in", 5, "--plot", tmp_path / "prop.png")
    run("identify", "propulsion", os.path.join(stand, "g8_7.csv"), "--pole-pairs", 1, "--diameter-in", 5,
        "--out", tmp_path / "prop-2s.json")
    run("validate", "propulsion", "--model", tmp_path / "prop-2s.json", os.path.join(stand, "g8_11.csv"),
        "--pole-pairs", 1, "--plot", tmp_path / "prop-validation.png")
    rows = ["airspeed_mps,pitch_deg,lift_n,drag_n,throttle_us"]
    for speed in (2.2, 4.5, 6.7, 8.9):  # Table 2.3's speeds, a drag area growing with |pitch|, one powered row
        rows += [f"{speed},{pitch},0,{0.6125 * (0.05 + 4e-4 * abs(pitch)) * speed ** 2},0"
                 for pitch in range(-30, 31, 15)]
    rows.append("4.5,0,0,1.0,1500")
    (tmp_path / "tunnel.csv").write_text("\n".join(rows) + "\n")
    run("identify", "drag", tmp_path / "tunnel.csv", "--plot", tmp_path / "drag.png")
    # The CLI draws beside the target and renames over it (".uascma-plot-PID-NAME"): the check sees that name.
    drawn = [dict(f, file=f["file"].split("-", 3)[-1] if f["file"].startswith(".uascma-plot-") else f["file"])
             for f in figures()]
    assert_clean(drawn, ["cell.png", "cell-validation.png", "prop.png", "prop-validation.png", "drag.png"])
