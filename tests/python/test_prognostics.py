"""EOD, RUL and the footprint from Python, against the CLI for the same inputs and seed."""
import numpy as np
import pytest

import uascma
from conftest import cli_json

ROUND_OFF = 1e-12


def test_eod_curve_shape_and_monotone_in_current():
    pack = uascma.BatteryPack()
    state = pack.resting_state(4.1)
    currents = np.array([[5.0, 10.0, 20.0], [30.0, 40.0, 60.0]])  # A
    eod = uascma.pack_eod_curve(pack, state, currents)
    assert eod.shape == (2, 3)
    # A larger constant current empties the battery sooner.
    assert np.all(np.diff(eod.ravel()) < 0.0)
    single = uascma.pack_eod(pack, state, 20.0)
    assert single.status == uascma.EodStatus.reached
    assert single.eod_s == eod[0, 2]


def test_eod_equals_the_cli():
    pack = uascma.BatteryPack(["M", "M"], 77.0)
    eod = uascma.pack_eod(pack, pack.resting_state(4.0), 25.0)
    cli = cli_json("eod", "--current-a", 25, "--initial-cell-voltage", 4.0, "--health", "M")
    assert eod.eod_s == pytest.approx(cli["eod_s"], rel=ROUND_OFF)


def test_rul_equals_the_cli_for_the_same_seed():
    rul, jam = uascma.rul(particles=50, seed=7, runs=200)
    cli = cli_json("rul", "--particles", 50, "--seed", 7, "--runs", 200)
    assert rul.rul_s.shape == (50,)
    assert rul.mean_s == pytest.approx(cli["rul_mean_s"], rel=ROUND_OFF)
    assert rul.p95_s == pytest.approx(cli["rul_p95_s"], rel=ROUND_OFF)
    assert jam.jam_probability_per_epoch == pytest.approx(cli["jam_probability_per_s"], rel=ROUND_OFF)
    # Another seed draws other particles.
    other, _ = uascma.rul(particles=50, seed=8, runs=10)
    assert other.mean_s != rul.mean_s


def test_rul_model_rejects_a_bad_field():
    params = uascma.SpallGrowthParams()
    params.particles = 0
    with pytest.raises(uascma.InputError, match="particles"):
        uascma.MotorRulModel(params)


def test_footprint_equals_the_cli_and_its_boundary_is_an_ellipse():
    params = uascma.FootprintParams(initial_speed=5.0, eod=12.0)
    # The CLI's default d_x is the drag table's slope at the given speed (FootprintParams' default: at 5 m/s).
    params.drag_slope = uascma.cruise_drag_slope(5.0)
    result = uascma.footprint(params)
    cli = cli_json("footprint", "--speed-mps", 5, "--eod-s", 12)
    assert params.drag_slope == pytest.approx(cli["drag_slope"], rel=ROUND_OFF)
    assert result.forward_limit == pytest.approx(cli["forward_m"], rel=ROUND_OFF)
    assert result.lateral_limit == pytest.approx(cli["lateral_m"], rel=ROUND_OFF)
    boundary = result.region.boundary(32)
    assert boundary.shape == (32, 2)
    region = result.region
    inside = ((boundary[:, 0] - region.center_x) / region.semi_axis_x) ** 2 + (boundary[:, 1] / region.semi_axis_y) ** 2
    np.testing.assert_allclose(inside, 1.0, rtol=1e-9)
    assert region.contains(boundary * 0.5 + [region.center_x * 0.5, 0.0]).all()


def test_footprint_names_the_bad_field():
    with pytest.raises(uascma.InputError, match="eod"):
        uascma.footprint(uascma.FootprintParams(initial_speed=5.0, eod=-1.0))


def test_eod_distribution_equals_the_cli():
    pack = uascma.BatteryPack()
    uncertainty = uascma.EodUncertainty()
    uncertainty.load_log_mean = 0.02
    uncertainty.load_log_sigma = 0.08
    uncertainty.soc_sigma = 0.02
    distribution = uascma.pack_eod_distribution(pack, pack.resting_state(4.1), 30.0, uncertainty)
    cli = cli_json("eod", "--current-a", 30, "--quantiles", "--load-log-mean", 0.02, "--load-log-sigma", 0.08,
                   "--soc-sigma", 0.02)["distribution"]
    levels = np.array(cli["levels"])
    assert distribution.quantiles(levels) == pytest.approx(cli["quantiles_s"], rel=ROUND_OFF)
    # P(EOD < q(p)) = p, and the quantiles increase.
    for p in levels:
        assert distribution.probability_before(distribution.quantile(p)) == pytest.approx(p, abs=1e-9)
    assert np.all(np.diff(distribution.quantiles(levels)) > 0.0)
    assert distribution.evaluations == 5  # point, centre (biased load), load, SOC both sides
    with pytest.raises(uascma.InputError):
        distribution.quantile(1.5)


def test_rul_calibration_equals_the_cli():
    python = uascma.rul_calibration(histories=200, seed=3, prognosis_time_per_step_s=0.7128)
    cli = cli_json("rul", "--calibrate", "--histories", 200, "--seed", 3, "--time-per-step", 0.7128)
    assert python.predictions == cli["predictions"]
    for mine, theirs in zip(python.report.intervals, cli["intervals"]):
        assert mine.covered == theirs["covered"]
    assert python.report.saxena.mean_relative_accuracy == pytest.approx(
        cli["saxena"]["mean_relative_accuracy"], rel=ROUND_OFF)


def test_calibration_report_of_a_grid():
    # Truths on a grid of the uniform distribution on [0, 100] s: each central interval covers its share.
    levels = uascma.standard_quantile_levels()
    n = 1000
    quantiles = np.tile(100.0 * np.array(levels), (n, 1))
    truths = (np.arange(n) + 0.5) / n * 100.0
    report = uascma.calibration_report(levels, quantiles, truths, np.zeros(n), np.arange(n))
    assert [c.covered for c in report.intervals] == [500, 800, 900, 950]
    assert report.pit_histogram == [100] * 10
    with pytest.raises(uascma.InputError):
        uascma.calibration_report(levels, quantiles[:, :3], truths, np.zeros(n), np.arange(n))
