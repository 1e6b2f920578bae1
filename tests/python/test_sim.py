"""Flights from Python: the same flight as `uascma simulate` for the same seed, telemetry arrays with the
right shapes and units, names in the telemetry CSV, Python callables as decision modules, and errors."""
import math
import os

import numpy as np
import pandas as pd
import pytest

import uascma
from conftest import example, run_cli, cli_json

# Fields of the summary that measure the host, not the flight.
WALL_CLOCK_FIELDS = ("wall_time_s", "realtime_factor")


# What `simulate --out` adds about the files it wrote (not part of the flight).
OUTPUT_LISTING_FIELDS = {"files", "qgc_plans"}


def without_wall_clock(summary):
    return {k: v for k, v in summary.items() if k not in set(WALL_CLOCK_FIELDS) | OUTPUT_LISTING_FIELDS}


@pytest.fixture(scope="module")
def nominal():
    return uascma.run(example("nominal.yaml"), "noop", seed=5)


def test_flight_equals_the_cli_for_the_same_seed(tmp_path, nominal):
    cli_dir, python_dir = tmp_path / "cli", tmp_path / "python"
    cli = cli_json("simulate", example("nominal.yaml"), "--policy", "noop", "--seed", 5, "--out", cli_dir)
    nominal.write(str(python_dir))
    assert without_wall_clock(nominal.summary()) == without_wall_clock(cli)
    for name in ("telemetry.csv", "plan.csv"):
        assert (python_dir / name).read_bytes() == (cli_dir / name).read_bytes(), name
    # Another seed is another flight (the Dryden gusts differ).
    other = uascma.run(example("nominal.yaml"), "noop", seed=6)
    assert other.telemetry()["p_W"][-1, 0] != nominal.telemetry()["p_W"][-1, 0]


def test_telemetry_arrays_have_shapes_and_units(nominal):
    t = nominal.telemetry()
    n = len(t["t_s"])
    assert n > 100
    for name, shape in (("p_W", (n, 3)), ("v_W", (n, 3)), ("euler", (n, 3)), ("wrench", (n, 4)),
                        ("rotor_thrust", (n, 6)), ("branch_current", (n, 2)), ("cell_voltage", (n, 2, 3)),
                        ("rul_s", (n,)), ("cma_state", (n,))):
        assert t[name].shape == shape, name
    # Rows at the scenario's 10 Hz telemetry rate (s).
    np.testing.assert_allclose(np.diff(t["t_s"]), 0.1, atol=1e-9)
    # Units: the vehicle flies at its 30 m cruise altitude (NED: z = −30 m) and cells stay between the
    # 3.3 V cut-off and their 4.1 V start (V); the pack current is the branch currents' sum (A).
    assert -t["p_W"][:, 2].min() == pytest.approx(30.0, abs=1.0)
    assert 3.3 < t["cell_voltage"].min() and t["cell_voltage"].max() <= 4.1 + 1e-9
    np.testing.assert_allclose(t["branch_current"].sum(axis=1), t["pack_current"], rtol=1e-9, atol=1e-9)
    # No fault: no RUL (NaN, not a sentinel).
    assert np.isnan(t["rul_s"]).all()
    assert nominal.plan().shape[1] == 4


def test_telemetry_csv_has_names_and_empty_fields(tmp_path, nominal):
    nominal.write(str(tmp_path))
    frame = uascma.read_telemetry(str(tmp_path))
    assert len(frame) == len(nominal.telemetry()["t_s"])
    assert frame["cma_state"].iloc[0] == "N,NF,MM1,G,RM1"
    assert set(frame["action"]) <= set(uascma.ACTION_NAMES)
    assert set(frame["imm_mode"]) <= set(uascma.IMM_MODE_NAMES)
    assert frame["rul_s"].isna().all()
    assert frame.attrs["summary"]["outcome"] == nominal.outcome
    # The CSV's own text: no sentinel numbers where a value does not exist.
    text = (tmp_path / "telemetry.csv").read_text()
    assert "-1000000000" not in text and ",-1.000," not in text
    in_memory = uascma.telemetry_frame(nominal)
    pd.testing.assert_frame_equal(in_memory, frame)


def test_jammed_rotor_shows_rul_and_the_isolated_rotor(tmp_path):
    flight = uascma.run(example("jam-motor-3.yaml"))
    flight.write(str(tmp_path))
    frame = uascma.read_telemetry(str(tmp_path))
    spall_onset_s = flight.summary()["spall_onset_s"]
    after = frame[frame["t_s"] > spall_onset_s + 1.0]
    assert after["rul_s"].notna().any()
    assert frame[frame["t_s"] < spall_onset_s]["rul_s"].isna().all()
    assert "rotor3_out" in set(frame["imm_mode"])
    assert (after["cma_state"].str.split(",").str[1] != "NF").all()
    # `uascma plot` reads the new CSV (python/plots/flight.py).
    run_cli("plot", tmp_path)
    for name in ("path.png", "eod.png", "decisions.png"):
        assert os.path.getsize(tmp_path / name) > 0, name


def test_a_python_callable_flies_like_the_same_policy_in_cpp():
    noop = uascma.run(example("nominal.yaml"), "noop", seed=3, telemetry=False)
    seen = []

    def always_noop(inputs):
        seen.append(inputs.time_s)
        assert isinstance(inputs.eod, uascma.EodValue)  # a Python policy sees the EOD's value, never its class's bound
        assert (inputs.eod_s, inputs.reach_margin) == (inputs.eod.eod_s, inputs.eod.reach_margin)
        return "NoOp"

    mine = uascma.run(example("nominal.yaml"), always_noop, seed=3, telemetry=False)
    assert mine.policy == "always_noop"
    assert without_wall_clock({**mine.summary(), "policy": "noop"}) == without_wall_clock(noop.summary())
    assert seen[:3] == [0.0, 1.0, 2.0]  # called at 1 Hz

    # The CMA table looked up in Python (the EOD's value at every epoch) flies exactly as the C++ table policy (the
    # EOD only as far as the reach margin's class needs).
    solution = uascma.solve_cma()
    table = uascma.run(example("jam-motor-3.yaml"), "cma", telemetry=False)
    python = uascma.run(example("jam-motor-3.yaml"), lambda i: int(solution.policy.action[i.state.index]),
                        telemetry=False)
    assert python.actions == table.actions
    assert python.outcome == table.outcome and python.sim_time_s == table.sim_time_s


def test_the_eod_distribution_reaches_telemetry_decision_inputs_and_the_summary(nominal):
    # The 5/50/95 % quantiles are ordered at every row, the chance of falling short is a probability.
    t = nominal.telemetry()
    flying = t["eod_s"] > 0
    assert flying.any()
    assert (t["eod_p05_s"][flying] <= t["eod_p50_s"][flying]).all()
    assert (t["eod_p50_s"][flying] <= t["eod_p95_s"][flying]).all()
    assert ((0 <= t["eod_short_probability"]) & (t["eod_short_probability"] <= 1)).all()
    # A Python callable sees the distribution; the CMA's first action records it in the summary.
    seen = []

    def watch(inputs):
        d = inputs.eod_distribution
        seen.append((d.p05_s, d.p95_s, d.short_probability))
        return "NoOp"

    uascma.run(example("nominal.yaml"), watch, telemetry=False)
    assert all(p05 <= p95 and 0 <= short <= 1 for p05, p95, short in seen[1:])
    acted = uascma.run(example("jam-motor-3.yaml"), "cma", telemetry=False).summary()["eod_at_first_action"]
    assert acted is None or acted["p05_s"] <= acted["p50_s"] <= acted["p95_s"]


def test_errors_raise_input_error_naming_the_field(tmp_path):
    with pytest.raises(uascma.InputError, match="wind.speedd_mps|speedd_mps"):
        uascma.run("name: typo\nwind:\n  speedd_mps: 2\n")
    with pytest.raises(uascma.InputError, match="vehicle.mass_kg"):
        uascma.run({"vehicle": {"mass_kg": -1.0}})
    with pytest.raises(uascma.InputError, match="scenario"):
        uascma.run(str(tmp_path / "missing.yaml"))
    with pytest.raises(uascma.InputError, match="action"):
        uascma.run(example("nominal.yaml"), lambda inputs: "Hover", telemetry=False)
    with pytest.raises(ValueError):  # InputError is a ValueError
        uascma.run(example("nominal.yaml"), "no-such-policy.json", telemetry=False)
    # An exception raised inside the Python policy reaches the caller unchanged.
    def broken(inputs):
        raise KeyError("from the policy")
    with pytest.raises(KeyError, match="from the policy"):
        uascma.run(example("nominal.yaml"), broken, telemetry=False)


def test_telemetry_written_with_codes_before_names_reads_the_same(tmp_path):
    # Files from before the CSV carried names: integer codes, -1 for "no RUL", -1e9 for MM = −∞.
    (tmp_path / "telemetry.csv").write_text(
        "t_s,rul_s,motor_margin,cma_state,action,imm_mode\n"
        "0.100,-1.000,1.00000,2,0,0\n"
        "0.200,0.000,-1000000000.00000,35,3,3\n")
    frame = uascma.read_telemetry(str(tmp_path))
    assert list(frame["cma_state"]) == [uascma.cma_state_label(2), uascma.cma_state_label(35)]
    assert list(frame["action"]) == ["NoOp", "LandPract"]
    assert list(frame["imm_mode"]) == ["nominal", "rotor3_out"]
    assert np.isnan(frame["rul_s"][0]) and frame["rul_s"][1] == 0.0
    assert frame["motor_margin"][0] == 1.0 and frame["motor_margin"][1] == -np.inf
    (tmp_path / "telemetry.csv").write_text("x,y\n1,2\n")
    with pytest.raises(uascma.InputError, match="t_s"):
        uascma.read_telemetry(str(tmp_path))


def test_the_summary_text_is_the_clis(nominal):
    """sim/flight_summary.h formats the text once: `uascma simulate` prints what Flight.summary_text() returns,
    but for the wall-clock line's timing."""
    cli = run_cli("simulate", example("nominal.yaml"), "--policy", "noop", "--seed", 5).stdout.splitlines()
    mine = nominal.summary_text().splitlines()
    assert len(mine) == len(cli)
    for a, b in zip(mine, cli):
        if a.startswith("flew "):  # "flew X s of simulated time in Y ms (Zx real time); ...": Y and Z are timings
            assert a.split(" in ")[0] == b.split(" in ")[0] and a.split(";")[1] == b.split(";")[1]
        else:
            assert a == b


def test_scenario_properties_come_from_the_field_table():
    scenario = uascma.load_scenario(example("nominal.yaml"))
    assert scenario.vehicle_mass_kg == scenario.mass
    scenario.wind_direction_deg = 90.0
    assert abs(scenario.wind_direction_deg - 90.0) < 1e-12  # held in radians, shown in degrees
    scenario.vehicle_inertia_kg_m2 = (0.01, 0.012, 0.02)
    assert scenario.vehicle_inertia_kg_m2 == (0.01, 0.012, 0.02)
    scenario.options_eod_load = "present"
    assert scenario.options_eod_load == "present"
    with pytest.raises(uascma.InputError):
        scenario.wind_turbulence = "hurricane"


def test_policies_on_beliefs_under_noisy_sensing(tmp_path):
    """options.noisy_sensing gives the decision module beliefs; cma-risk and cma-qmdp are policies by name,
    and without noise they fly the cma flight."""
    exact = uascma.run(example("jam-motor-3.yaml"), "cma", telemetry=False)
    for name in ("cma-risk", "cma-qmdp"):
        other = uascma.run(example("jam-motor-3.yaml"), name, telemetry=False)
        assert other.actions == exact.actions and other.sim_time_s == exact.sim_time_s, name
    text = open(example("jam-motor-3.yaml")).read() + "options: {noisy_sensing: true}\n"
    noisy_path = tmp_path / "noisy.yaml"
    noisy_path.write_text(text)
    beliefs = []

    def record(inputs):
        beliefs.append((inputs.time_s, tuple(inputs.motor_health_belief), inputs.eod_distribution.short_probability))
        return "NoOp"

    flight = uascma.run(str(noisy_path), record)
    assert all(abs(sum(b) - 1.0) < 1e-12 for _, b, _ in beliefs)
    # The telemetry carries the same belief, one row per GNC step (it changes at the 1 Hz epochs).
    belief = flight.telemetry()["motor_health_belief"]
    assert belief.shape[1] == 3 and abs(belief.sum(axis=1) - 1.0).max() < 1e-12
    assert belief[:, 1:].sum(axis=1).max() == max(b[1] + b[2] for _, b, _ in beliefs)
    assert all(0.0 <= p <= 1.0 for _, _, p in beliefs)
    # The spall starts at 60 s: the belief in SF or JF rises above the prior afterwards.
    assert max(b[1] + b[2] for t, b, _ in beliefs if t > 60.0) > 0.5
    assert uascma.run(str(noisy_path), "cma-qmdp", telemetry=False).outcome
    # The vehicle-level belief policies by name: without noise they fly the cma-vehicle flight.
    exact_vehicle = uascma.run(example("jam-motor-3.yaml"), "cma-vehicle", telemetry=False)
    for name in ("cma-vehicle-risk", "cma-vehicle-qmdp"):
        other = uascma.run(example("jam-motor-3.yaml"), name, telemetry=False)
        assert other.actions == exact_vehicle.actions and other.sim_time_s == exact_vehicle.sim_time_s, name
    scenario = uascma.load_scenario(str(noisy_path))
    assert scenario.options_noisy_sensing is True


def test_cma_vehicle_is_a_policy_by_name_and_its_margin_is_an_input():
    """cma-vehicle resolves by name; a Python policy sees the vehicle-level motor margin, which is eq. 5.14's value
    (1 without a fault) until the spall's RUL falls short of the plan (sim/vehicle_margin.h)."""
    seen = []

    def record(inputs):
        seen.append((inputs.rul_s, inputs.motor_margin, inputs.vehicle_motor_margin))
        return "NoOp"

    uascma.run(example("jam-motor-3.yaml"), record, telemetry=False)
    assert seen and all(v == m == 1.0 for r, m, v in seen if math.isinf(r))
    assert any(not math.isinf(r) for r, _, _ in seen)
    assert uascma.run(example("jam-motor-3.yaml"), "cma-vehicle", telemetry=False).outcome
