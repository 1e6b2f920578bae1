"""uascma: risk-aware Contingency Management Autonomy (CMA) for small multicopter drones, from Python.

The compiled core (``uascma._uascma``, pybind11 over the C++ library) is re-exported here whole, with the
pandas readers of :mod:`uascma.frames`. Build it with ``make build`` and put the build's python folder on
the path::

    PYTHONPATH=build/python /usr/bin/python3 -c "import uascma; print(uascma.run('examples/nominal.yaml'))"

Conventions
-----------
* Units are SI unless a name says otherwise (``_degf``, ``_mm2``, ``_us``, ``_rpm``, ``_ah``); frames are in
  the names: W is NED (north, east, down), B is FRD (forward, right, down).
* Arrays are NumPy float64 arrays; every function's docstring gives the shapes, e.g. ``(N, 3)``.
* Bad input raises :class:`uascma.InputError` (a ``ValueError``) whose message names the source, the field
  and what was expected, as the command-line tool prints it before exiting with code 2.

Areas
-----
* models: ``PropulsionParams``, ``rotor_thrust``, ``electrical_power``, ``estimate_rpm``, ``Mixer``,
  ``control_authority``, ``Cell``, ``BatteryPack`` (``simulate_discharge``).
* prognostics: ``pack_eod``, ``pack_eod_curve``, ``MotorRulModel``, ``rul``.
* planning: ``FootprintParams``, ``footprint``.
* decision: ``build_mdp``, ``solve``, ``evaluate_policy``, ``CmaWeights``, ``build_cma_mdp``, ``solve_cma``,
  ``load_policy``, ``read_policy_file``.
* simulation: ``load_scenario``, ``run`` (a flight with a named policy, a solved table or a Python
  callable), ``Flight`` (``summary``, ``telemetry``, ``write``), ``Environment`` (Gym-style ``reset(seed)`` →
  ``Observation``; ``step(action)`` → ``(observation, reward, done, info)`` at the 1 Hz decision epoch).
* campaigns: ``run_campaign``, ``read_records``; pandas: ``read_campaign``, ``read_telemetry``.
"""
from ._uascma import *  # noqa: F401,F403
from ._uascma import InputError, __version__  # noqa: F401
from .frames import read_campaign, read_telemetry, telemetry_frame, ACTION_NAMES, IMM_MODE_NAMES  # noqa: F401
