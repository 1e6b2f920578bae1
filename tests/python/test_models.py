"""Component models from Python: NumPy shapes and SI units, closed forms, and the CLI's numbers."""
import math

import numpy as np
import pytest

import uascma
from conftest import cli_json

# Round-off of a few double operations on values of order 1-100 (N, W, V).
ROUND_OFF = 1e-12
GRAVITY = 9.80665  # m/s², uascma/common/frames.h kGravity


def test_rotor_thrust_keeps_the_shape_and_is_eq_2_1():
    params = uascma.PropulsionParams()
    speed = np.linspace(0.0, 2000.0, 12).reshape(3, 4)  # rad/s
    thrust = uascma.rotor_thrust(params, speed)
    assert thrust.shape == (3, 4)
    rpm = speed * 60.0 / (2.0 * math.pi)
    np.testing.assert_allclose(thrust, params.thrust_coefficient_n_per_rpm2 * rpm**2, rtol=ROUND_OFF)
    # The inverse returns the speed (rad/s).
    np.testing.assert_allclose(uascma.rotor_speed_for_thrust(params, thrust), speed, rtol=1e-12, atol=1e-9)


def test_electrical_power_passes_through_table_2_2_per_rotor():
    # Table 2.2 (tractor) divided by six: 15 N / 6 at 286 W / 6 and 26.85 N / 6 at 578 W / 6 (propulsion.h).
    params = uascma.PropulsionParams.for_configuration("tractor")
    power = uascma.electrical_power(params, np.array([15.0 / 6.0, 26.85 / 6.0]))
    np.testing.assert_allclose(power, [47.67, 96.33], rtol=1e-3)


def test_static_thrust_equals_the_cli():
    for configuration, throttle, power in (("tractor", 1500, 286), ("pusher", 1900, 581)):
        mine = uascma.estimate_static_thrust(configuration, throttle, power)
        cli = cli_json("thrust", "--config", configuration, "--throttle-us", throttle, "--power-w", power)
        assert mine["total_thrust"] == pytest.approx(cli["thrust_n"], rel=ROUND_OFF)
        assert mine["rpm"] == pytest.approx(cli["rpm"], rel=ROUND_OFF)


def test_unknown_configuration_raises_input_error_naming_the_field():
    with pytest.raises(uascma.InputError, match="configuration") as error:
        uascma.PropulsionParams.for_configuration("upside-down")
    assert isinstance(error.value, ValueError)


def test_mixer_matrices_and_hover_allocation():
    mixer = uascma.Mixer()
    assert mixer.mixing_matrix(0).shape == (4, 6)
    assert mixer.allocation_matrix(3).shape == (6, 4)
    # The failure rule zeroes the failed motor's column and its opposite's (3 ↔ 6).
    np.testing.assert_array_equal(mixer.mixing_matrix(3)[:, [2, 5]], np.zeros((4, 2)))
    weight = 1.3 * GRAVITY
    result = mixer.allocate(np.array([weight, 0.0, 0.0, 0.0]), 0)
    assert result.rotor_thrust.shape == (6,)
    np.testing.assert_allclose(result.rotor_thrust, np.full(6, weight / 6.0), rtol=1e-12)
    np.testing.assert_allclose(result.achieved, [weight, 0, 0, 0], atol=1e-12)
    with pytest.raises(uascma.InputError, match="motor"):
        mixer.allocate(np.zeros(4), 7)


def test_control_authority_is_the_closed_form():
    mixer = uascma.Mixer()
    mass = 1.3
    for failed, rotors in ((0, 6), (2, 4)):
        authority = uascma.control_authority(mixer, failed, mass)
        expected = math.acos(math.sqrt(mass * GRAVITY / (rotors * mixer.params.max_rotor_thrust)))
        assert authority.active_rotors == rotors
        assert authority.max_tilt == pytest.approx(expected, rel=1e-9)


def test_pack_discharge_shapes_and_coulomb_counting():
    pack = uascma.BatteryPack(["G", "G"])
    state = pack.resting_state(4.1)
    assert state.soc_fraction.shape == (2, 3)
    current_a, dt_s, steps = 20.0, 0.5, 240
    run = pack.simulate_discharge(state, np.full(steps, current_a), dt_s)
    assert run["cell_voltage_v"].shape == (steps, 2, 3)
    assert run["soc_fraction"].shape == (steps, 2, 3)
    assert run["branch_current_a"].shape == (steps, 2)
    assert run["bus_voltage_v"].shape == (steps,)
    # Two identical packs share the current equally (eqs. 3.4-3.5).
    np.testing.assert_allclose(run["branch_current_a"], current_a / 2.0, rtol=1e-9)
    # Coulomb counting, η_discharge = 1 (Table 3.1): each cell loses I/2 · t / (Q · 3600 s/h) of charge.
    final = run["final_state"].soc_fraction
    capacity_ah = np.array([uascma.CellParams.table_3_1(c).capacity_ah for c in (1, 2, 3)])
    expected = state.soc_fraction - (current_a / 2.0) * steps * dt_s / (capacity_ah * 3600.0)
    np.testing.assert_allclose(final, expected, rtol=1e-12)
    # Under a constant discharge the state of charge never rises.
    assert np.all(np.diff(run["soc_fraction"], axis=0) < 0.0)


def test_resting_state_outside_the_ocv_table_raises():
    pack = uascma.BatteryPack()
    with pytest.raises(uascma.InputError, match="voltage"):
        pack.resting_state(5.0)
    with pytest.raises(uascma.InputError, match=r"\(2, 3\)"):
        pack.resting_state(np.full((3, 2), 4.0))
    with pytest.raises(uascma.InputError, match="packs"):
        uascma.BatteryPack(["G", "Q"])
