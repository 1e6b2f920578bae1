"""uascma: risk-aware Contingency Management Autonomy (CMA) for small multicopter drones, from Python.

The compiled core (``uascma._uascma``, pybind11 over the C++ library) is re-exported here whole. Build it with
``make build`` and put the build's python folder on the path::

    PYTHONPATH=build/python /usr/bin/python3 -c "import uascma; print(uascma.run(uascma.example_file('nominal.yaml')))"

Conventions
-----------
* Units are SI unless a name says otherwise (``_degf``, ``_mm2``, ``_us``, ``_rpm``, ``_ah``); frames are in
  the names: W is NED (north, east, down), B is FRD (forward, right, down).
* Arrays are NumPy float64 arrays; every function's docstring gives the shapes, e.g. ``(N, 3)``. Wherever an
  integer is taken (an action, a seed, a count) a NumPy integer is taken too.
* Bad input raises :class:`uascma.InputError` (a ``ValueError``) whose message names the source, the field
  and what was expected, as the command-line tool prints it before exiting with code 2.
* The mission importer's notes (items read but not modelled) are Python warnings of category
  :class:`uascma.MissionWarning`.
* Long calls (``run_campaign``, ``run``) stop within a second on Ctrl-C (KeyboardInterrupt); a campaign keeps
  every finished flight and continues with ``resume=True``. ``run_campaign(progress=…)`` reports progress.
* ``import uascma`` loads neither pandas nor NumPy; the pandas readers and the environment load what they need
  on first use.

Areas
-----
* models: ``PropulsionParams``, ``rotor_thrust``, ``electrical_power``, ``estimate_rpm``, ``Mixer``,
  ``control_authority``, ``Cell``, ``BatteryPack`` (``simulate_discharge``).
* prognostics: ``pack_eod``, ``pack_eod_curve``, ``pack_eod_distribution`` (``EodUncertainty``), ``MotorRulModel``, ``rul``.
* planning: ``FootprintParams``, ``footprint``.
* decision: ``build_mdp``, ``solve``, ``evaluate_policy``, ``CmaWeights``, ``build_cma_mdp``, ``solve_cma``,
  ``load_policy``, ``read_policy_file``.
* simulation: ``load_scenario``, ``run`` (a flight with a named policy, a solved table or a Python
  callable), ``Flight`` (``summary``, ``telemetry``, ``write``), ``Environment`` (Gymnasium's API:
  ``reset(seed=None, options=None)`` → ``(observation, info)``; ``step(action)`` → ``(observation, reward,
  terminated, truncated, info)``; ``observation_space``, ``action_space``; ``snapshot()`` and
  ``restore(snapshot)`` branch a flight), ``example_file``.
* campaigns: ``run_campaign``, ``read_records``; pandas: ``read_campaign``, ``read_telemetry``,
  ``telemetry_frame``.
"""
import os as _os

from . import _uascma
from ._uascma import *  # noqa: F401,F403
from ._uascma import InputError, MissionWarning, __version__  # noqa: F401
from ._examples import example_file, example_files  # noqa: F401
from ._names import ACTION_NAMES, IMM_MODE_NAMES  # noqa: F401

TYPE_CHECKING = False  # typing.TYPE_CHECKING without importing typing (type checkers take the name as True)
if TYPE_CHECKING:  # what the lazy attributes below are, for type checkers and editors
    from .env import Environment  # noqa: F401
    from .frames import read_campaign, read_telemetry, telemetry_frame  # noqa: F401
    from .spaces import Discrete  # noqa: F401


def run_campaign(config, db, runs=None, policies=None, seed=None, jobs=0, resume=False, progress=True, runs_in_flight=4):
    """Runs (or resumes) a campaign into the SQLite file ``db``, as ``uascma campaign CONFIG --db DB [--runs N]
    [--policies a,b] [--seed S] [--jobs J] [--resume] [--runs-in-flight R]``; returns a dict of counts and the wall
    time (s).

    config: a campaign YAML path, YAML text, a dict, a CampaignConfig or None (the defaults).
    runs: 0 to 10^7 (None: the file's); seed: 0 to 2^64-1 (None: the file's); jobs: 0 (every core) to 1024 threads,
    as the CLI's bounds. Integers only (NumPy integers too): anything else, or a value outside its range, is an
    InputError naming the argument and the range.
    progress: True (tqdm when installed, else a line on sys.stderr every 10 s or 5 %), False/None (nothing),
    or a callable ``progress(done, total)`` counting flights.
    runs_in_flight: runs each thread flies at once, their flights stepped in lockstep four at a time in SIMD lanes
    (1 to 64; 1: one run at a time). The stored rows are the same whatever it is (``wall_time_s`` apart).
    Ctrl-C stops it within a second: the flights in progress finish, every finished flight is stored, and the
    KeyboardInterrupt says how many; the same call with ``resume=True`` continues the campaign.
    """
    from ._progress import make_reporter

    reporter = make_reporter(progress)
    try:
        return _uascma.run_campaign(config, _os.fspath(db), runs=runs, policies=policies, seed=seed, jobs=jobs, resume=resume,
                                    progress=reporter, runs_in_flight=runs_in_flight)
    finally:
        if reporter is not None:
            reporter.close()


# Loaded on first use: pandas (frames), NumPy and gymnasium (env, spaces) cost far more than the core.
_LAZY = {
    "Environment": "env",
    "Discrete": "spaces",
    "read_campaign": "frames",
    "read_telemetry": "frames",
    "telemetry_frame": "frames",
}


def __getattr__(name):
    module = _LAZY.get(name)
    if module is None:
        raise AttributeError(f"module 'uascma' has no attribute {name!r}")
    from importlib import import_module

    value = getattr(import_module(f".{module}", __name__), name)
    globals()[name] = value
    return value


def __dir__():
    return sorted(set(globals()) | set(_LAZY))
