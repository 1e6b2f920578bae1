"""uascma.Environment: the simulator as a Gymnasium environment at the CMA's 1 Hz decision epoch.

Gymnasium's API (gymnasium.Env; a subclass of it when the gymnasium package is installed, the same methods and
attributes without it)::

    env = uascma.Environment(uascma.example_file("jam-motor-3.yaml"))
    observation, info = env.reset(seed=42)
    for _ in range(1000):
        action = env.action_space.sample()
        observation, reward, terminated, truncated, info = env.step(action)
        if terminated or truncated:
            observation, info = env.reset()
    env.close()

* observation: the CMA state index, an ``np.int64`` in ``observation_space = Discrete(112)``: 0-107 the
  (FS, MH, MM, BH, RM) tuples, 108-110 the terminals C, T, FL (uascma.cma_state_label names them);
  ``info["observation"]`` is the uascma.Observation behind it (time, EOD, RUL, margins, flight status).
* action: ``action_space = Discrete(4)``, 0 NoOp, 1 Terminate, 2 LandASAP, 3 LandPract; a Python or NumPy
  integer, a 0-d integer array, a uascma.CmaAction or a name. ``info["action_mask"]`` (int8, shape (4,)) marks
  the actions the flight status offers (docs/modelling-choices.md#action-availability), for
  ``action_space.sample(info["action_mask"])``.
  An action it does not offer is executed as NoOp (the emergency plan under way goes on; ``info["executed"]``
  and ``info["requested"]`` say so) with ``unavailable="noop"`` (the default, so that any sampled action is
  valid), or raises uascma.InputError with ``unavailable="raise"``.
* reward: R(S, A) of eqs. 5.20-5.29 for the state and the executed action; when the flight ends it also holds
  the terminal's own reward, so an episode's return is the campaign's reward trace of the same flight.
* terminated: the flight has ended (every end is a terminal state of the CMA MDP: C, T, or FL, a timeout being
  a failure); truncated: always False (the environment imposes no limit of its own; wrap it in Gymnasium's
  TimeLimit for one).
* snapshot() / restore(snapshot): the flight copied whole at an epoch, and continued from the copy as often as
  wanted (each branch bit for bit the flight the copy came from would fly; sim/branching.h on the C++ side).
* reset(seed=None, options=None): seed None replays the scenario's seed on the first reset, then the next
  seed after the last one flown (reproducible episodes); ``options`` takes no keys.
"""
import numpy as np

from . import _uascma
from .spaces import HAVE_GYMNASIUM, Discrete

_NOOP = 0

if HAVE_GYMNASIUM:  # pragma: no cover - depends on the machine
    import gymnasium

    _Base = gymnasium.Env
else:

    class _Base:
        """What gymnasium.Env gives an environment, for machines without gymnasium."""

        metadata = {"render_modes": []}
        render_mode = None
        spec = None

        def close(self):
            pass

        def render(self):
            return None

        @property
        def unwrapped(self):
            return self

        def __enter__(self):
            return self

        def __exit__(self, *exc):
            self.close()
            return False

        def __str__(self):
            return f"<{type(self).__name__} instance>"


def _action_index(action):
    """The action's index 0-3 from an int, a NumPy integer or 0-d array, a CmaAction or a name."""
    if isinstance(action, _uascma.CmaAction):
        return int(action)
    if isinstance(action, str):
        return int(_uascma.CmaAction.__members__[action]) if action in _uascma.CmaAction.__members__ else action
    if isinstance(action, np.ndarray) and action.shape == (1,):
        action = action[0]
    return action  # validated by the compiled environment (InputError naming the value)


class Environment(_Base):
    """The simulator as a Gymnasium environment at the CMA's 1 Hz decision epoch (module docstring)."""

    metadata = {"render_modes": []}
    render_mode = None

    def __init__(self, scenario, weights=None, record=False, record_telemetry=False, unavailable="noop",
                 mission=None):
        """scenario: a path, YAML text, a dict or a uascma.Scenario; weights: uascma.CmaWeights of R(S, A) (eqs.
        5.28-5.29 by default); record / record_telemetry: keep the flight's log (flight()); unavailable: "noop"
        or "raise" (module docstring); mission: a .plan or .waypoints file flown instead of the scenario's."""
        if unavailable not in ("noop", "raise"):
            raise _uascma.InputError(f"Environment: unavailable: 'noop' or 'raise', got {unavailable!r}")
        self._unavailable = unavailable
        self._env = _uascma.DecisionEnvironment(scenario, weights=weights, record=record,
                                                record_telemetry=record_telemetry,
                                                require_available_actions=True, mission=mission)
        self.observation_space = Discrete(_uascma.CMA_NUM_STATES)
        self.action_space = Discrete(len(_uascma.CmaAction.__members__))
        self.reward_range = (-float("inf"), float("inf"))
        self._next_seed = int(self._env.scenario_seed)
        self._observation = None

    @staticmethod
    def _info(observation):
        return {"observation": observation, "state_label": observation.state_label, "time_s": observation.time_s,
                "action_mask": np.asarray(observation.action_mask, dtype=np.int8)}

    def reset(self, *, seed=None, options=None):
        """A new flight: (observation, info). seed: an int (NumPy integers too) or None (module docstring)."""
        if HAVE_GYMNASIUM:  # pragma: no cover
            super().reset(seed=None if seed is None else int(seed))  # seeds self.np_random, as Gymnasium does
        if options is not None:
            if not isinstance(options, dict):
                raise _uascma.InputError(f"reset: options: None or a dict, got {type(options).__name__}")
            if options:
                raise _uascma.InputError(f"reset: options: no options are defined, got {sorted(options)}")
        if seed is not None:
            if isinstance(seed, bool) or not isinstance(seed, (int, np.integer)) or int(seed) < 0:
                raise _uascma.InputError(f"reset: seed: a non-negative integer or None, got {seed!r}")
            self._next_seed = int(seed)
        flight_seed = self._next_seed
        self._next_seed = (flight_seed + 1) % (1 << 64)
        observation = self._env.reset(flight_seed)
        self._observation = observation
        info = self._info(observation)
        info["seed"] = flight_seed
        return np.int64(observation.state_index), info

    def step(self, action):
        """Executes a CMA action and flies to the next epoch: (observation, reward, terminated, truncated, info)."""
        index = _action_index(action)
        if (self._unavailable == "noop" and self._observation is not None and not self._observation.terminal
                and isinstance(index, (int, np.integer)) and 0 <= int(index) < 4
                and not self._observation.action_mask[int(index)]):
            requested = _uascma.CmaAction(int(index)).name
            observation, reward, done, info = self._env.step(_NOOP)
            info["requested"] = requested
        else:
            observation, reward, done, info = self._env.step(index)
        self._observation = observation
        info.update(self._info(observation))
        return np.int64(observation.state_index), float(reward), bool(done), False, info

    # Branching: a flight copied whole at an epoch and continued from the copy (MuJoCo's mj_copyData).
    def snapshot(self):
        """The flight now, whole (a uascma.FlightSnapshot: its state with the random streams, and its log)."""
        return self._env.snapshot()

    def restore(self, snapshot):
        """Continues from `snapshot` (taken of this environment's flights): (observation, info) as reset gives;
        each branch from one snapshot flies as the copied flight would have, bit for bit."""
        observation = self._env.restore(snapshot)
        self._observation = observation
        return np.int64(observation.state_index), self._info(observation)

    # The flight behind the environment.
    @property
    def decision_environment(self):
        """The compiled uascma.DecisionEnvironment this wraps."""
        return self._env

    @property
    def done(self):
        return self._env.done

    @property
    def time_s(self):
        return self._env.time_s

    def flight(self, policy="environment"):
        """The flight so far as a uascma.Flight (events, actions and states with record=True; telemetry with
        record_telemetry=True)."""
        return self._env.flight(policy)

    def close(self):
        pass

    def render(self):
        return None
