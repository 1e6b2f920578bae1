"""The decision environment (sim::DecisionEnvironment) stepped from Python through Gymnasium's API."""
import importlib.util
import math

import numpy as np
import pytest

import uascma
from conftest import example

WALL_CLOCK_FIELDS = ("wall_time_s", "realtime_factor", "policy")


def fly(env, decide, seed=None):
    """Steps a flight to its end; returns the uascma.Observations, rewards and the last info.
    decide(observation) takes the uascma.Observation behind the state index."""
    _, info = env.reset(seed=seed)
    observations, rewards = [info["observation"]], []
    terminated = truncated = False
    while not (terminated or truncated):
        state, reward, terminated, truncated, info = env.step(decide(info["observation"]))
        assert state == info["observation"].state_index
        observations.append(info["observation"])
        rewards.append(reward)
    return observations, rewards, info


def test_noop_episode_is_the_noop_flight_of_run():
    env = uascma.Environment(example("nominal.yaml"), record=True)
    observations, rewards, info = fly(env, lambda obs: uascma.CmaAction.NoOp, seed=4)
    flight = uascma.run(example("nominal.yaml"), "noop", seed=4, telemetry=False)
    assert info["outcome"] == flight.outcome
    mine = {k: v for k, v in env.flight().summary().items() if k not in WALL_CLOCK_FIELDS}
    theirs = {k: v for k, v in flight.summary().items() if k not in WALL_CLOCK_FIELDS}
    assert mine == theirs
    # One observation per 1 Hz epoch, from t = 0 s.
    times = [o.time_s for o in observations[:-1]]
    np.testing.assert_allclose(times, np.arange(len(times)), atol=1e-9)
    assert observations[0].state_label == "N,NF,MM1,G,RM1"
    assert observations[-1].state_label == "C"  # completed
    assert all(math.isfinite(r) for r in rewards)


def test_the_cma_table_through_the_environment_flies_like_run_with_cma():
    solution = uascma.solve_cma()
    env = uascma.Environment(example("jam-motor-3.yaml"), record=True)
    _, _, info = fly(env, lambda obs: int(solution.policy.action[obs.state_index]))
    flight = uascma.run(example("jam-motor-3.yaml"), "cma", telemetry=False)
    assert info["outcome"] == flight.outcome
    assert env.flight().actions == flight.actions
    assert env.flight().sim_time_s == flight.sim_time_s


def test_reward_is_r_of_state_and_action_with_the_weights():
    # Doubling every weight doubles every reward (eqs. 5.20-5.29 are linear in the weights).
    base = uascma.CmaWeights()
    doubled = uascma.CmaWeights(**{name: 2.0 * base.get(name) for name in uascma.CmaWeights.names()})
    _, rewards, _ = fly(uascma.Environment(example("nominal.yaml")), lambda obs: "NoOp", seed=2)
    _, rewards2, _ = fly(uascma.Environment(example("nominal.yaml"), weights=doubled), lambda obs: "NoOp", seed=2)
    np.testing.assert_allclose(rewards2, 2.0 * np.array(rewards), rtol=1e-12)


def test_misuse_raises_input_error():
    env = uascma.Environment(example("nominal.yaml"), unavailable="raise")
    with pytest.raises(uascma.InputError, match="Reset"):
        env.step("NoOp")
    env.reset()
    with pytest.raises(uascma.InputError, match="action"):
        env.step("Hover")
    with pytest.raises(uascma.InputError, match="action"):
        env.step(7)
    with pytest.raises(uascma.InputError, match="options"):
        env.reset(options={"wind": 3})
    with pytest.raises(uascma.InputError, match="seed"):
        env.reset(seed=-1)
    while not env.done:
        env.step("NoOp")
    with pytest.raises(uascma.InputError, match="ended"):
        env.step("NoOp")


def test_gymnasium_documented_loop():
    # The agent-environment loop exactly as Gymnasium's "Basic Usage" page writes it (gymnasium.farama.org,
    # content/basic_usage), with uascma.Environment in place of gym.make(...).
    env = uascma.Environment(example("jam-motor-3.yaml"))
    steps = episodes = 0
    observation, info = env.reset(seed=42)
    for _ in range(1000):
        action = env.action_space.sample()  # agent policy that uses the observation and info
        observation, reward, terminated, truncated, info = env.step(action)
        assert env.observation_space.contains(observation)
        assert math.isfinite(reward) and isinstance(terminated, bool) and isinstance(truncated, bool)
        steps += 1
        if terminated or truncated:
            episodes += 1
            observation, info = env.reset()
    env.close()
    assert steps == 1000
    # At most one epoch per second of flight (1 Hz) and the flights are minutes long: several episodes ended.
    assert episodes >= 1


def test_spaces_are_gymnasium_shaped():
    env = uascma.Environment(example("nominal.yaml"))
    assert env.action_space.n == 4 and env.action_space.shape == ()
    assert env.observation_space.n == uascma.CMA_NUM_STATES and env.observation_space.shape == ()
    assert repr(env.action_space) == "Discrete(4)"
    env.action_space.seed(5)
    draws = [env.action_space.sample() for _ in range(200)]
    assert all(isinstance(a, np.integer) and env.action_space.contains(a) for a in draws)
    assert set(int(a) for a in draws) == {0, 1, 2, 3}  # P(a value missing in 200 uniform draws) < 4 · 0.75^200
    assert not env.action_space.contains(4) and not env.action_space.contains(-1)
    assert not env.action_space.contains(1.0) and not env.action_space.contains("NoOp")
    masked = [env.action_space.sample(mask=np.array([1, 1, 0, 0], dtype=np.int8)) for _ in range(50)]
    assert set(int(a) for a in masked) <= {0, 1}
    state, info = env.reset(seed=3)
    assert isinstance(state, np.int64) and env.observation_space.contains(state)
    assert set(info) >= {"observation", "action_mask", "state_label", "seed"}
    np.testing.assert_array_equal(info["action_mask"], [1, 1, 1, 1])  # flight status N offers all four
    assert info["action_mask"].dtype == np.int8


def test_numpy_actions_and_seeds_are_taken():
    q = np.array([0.1, -2.0, -3.0, 0.0])
    env = uascma.Environment(example("nominal.yaml"))
    env.reset(seed=np.uint64(4))
    for action in (np.argmax(q), np.int32(0), np.array(0), np.array([0]), uascma.CmaAction.NoOp, "NoOp", 0):
        _, _, _, _, info = env.step(action)
        assert info["executed"] == "NoOp"
    flight = uascma.run(example("nominal.yaml"), "noop", seed=np.int64(4), telemetry=False)
    assert flight.seed == 4


def test_seeds_replay_and_advance():
    env = uascma.Environment(example("jam-motor-3.yaml"))
    scenario_seed = uascma.load_scenario(example("jam-motor-3.yaml")).seed
    _, first = env.reset()
    _, second = env.reset()
    _, again = env.reset(seed=scenario_seed)
    assert first["seed"] == scenario_seed and second["seed"] == scenario_seed + 1 and again["seed"] == scenario_seed


def test_unavailable_action_is_noop_by_default_and_raises_on_request():
    # docs/modelling-choices.md#action-availability: once LandASAP executes (ELASAP) only NoOp and Terminate are
    # offered.
    for unavailable in ("noop", "raise"):
        env = uascma.Environment(example("scenario-1.yaml"), unavailable=unavailable)  # over a city: sites
        env.reset(seed=1)
        for _ in range(30):  # airborne: LandASAP before take-off grounds the flight (it ends)
            env.step("NoOp")
        _, _, _, _, info = env.step("LandASAP")
        assert info["observation"].flight_status == uascma.FlightStatus.ELASAP
        np.testing.assert_array_equal(info["action_mask"], [1, 1, 0, 0])
        if unavailable == "raise":
            with pytest.raises(uascma.InputError, match="available"):
                env.step("LandPract")
        else:
            _, _, _, _, info = env.step("LandPract")
            assert info["requested"] == "LandPract" and info["executed"] == "NoOp"


@pytest.mark.skipif(importlib.util.find_spec("gymnasium") is None, reason="gymnasium is not installed")
def test_matches_gymnasium_where_installed():
    import gymnasium
    from gymnasium.utils.env_checker import check_env

    env = uascma.Environment(example("nominal.yaml"))
    assert isinstance(env, gymnasium.Env)
    assert isinstance(env.action_space, gymnasium.spaces.Discrete)
    check_env(env, skip_render_check=True)


# --- Gymnasium's checks made by our own code (the package index cannot be reached from every machine) ----------
def equivalent(a, b):
    """Whether two returned values are the same data: the same type, then dicts key by key, lists and tuples element
    by element, arrays by shape, dtype and every element, anything else by == (what gymnasium.utils.env_checker
    demands of two seeded resets or steps)."""
    if type(a) is not type(b):
        return False
    if isinstance(a, dict):
        return a.keys() == b.keys() and all(equivalent(a[k], b[k]) for k in a)
    if isinstance(a, (list, tuple)):
        return len(a) == len(b) and all(equivalent(x, y) for x, y in zip(a, b))
    if isinstance(a, np.ndarray):
        return a.shape == b.shape and a.dtype == b.dtype and bool(np.all(a == b))
    return bool(a == b)


def test_our_checker_can_fail():
    class Opaque:  # an object without ==, as Observation was
        pass

    assert not equivalent(Opaque(), Opaque())
    assert not equivalent({"a": np.zeros(2, np.int8)}, {"a": np.zeros(2, np.int16)})
    assert not equivalent(np.int64(1), 1)
    env = uascma.Environment(example("nominal.yaml"))
    _, info_a = env.reset(seed=1)
    _, info_b = env.reset(seed=2)
    assert not equivalent(info_a, info_b)  # another seed: another "seed" at least


def test_seeded_resets_are_the_same_data_in_one_environment_and_in_two():
    first, second = uascma.Environment(example("jam-motor-3.yaml")), uascma.Environment(example("jam-motor-3.yaml"))
    obs_1, info_1 = first.reset(seed=123)
    obs_2, info_2 = first.reset(seed=123)
    obs_3, info_3 = second.reset(seed=123)
    for obs, info in ((obs_2, info_2), (obs_3, info_3)):
        assert equivalent(obs_1, obs) and equivalent(info_1, info)
    assert first.observation_space.contains(obs_1)
    assert info_1["observation"] == info_3["observation"] and info_1["observation"].state == info_3["observation"].state


def test_seeded_steps_are_the_same_data_and_inside_the_spaces():
    env = uascma.Environment(example("jam-motor-3.yaml"))
    env.action_space.seed(123)
    actions = [env.action_space.sample() for _ in range(40)]
    results = []
    for _ in range(2):
        _, info = env.reset(seed=123)
        steps = []
        for action in actions:
            step = env.step(action)
            observation, reward, terminated, truncated, info = step
            assert env.observation_space.contains(observation)
            assert type(reward) is float and type(terminated) is bool and type(truncated) is bool
            assert isinstance(info, dict) and info["action_mask"].dtype == np.int8 and info["action_mask"].shape == (4,)
            steps.append(step)
            if terminated or truncated:
                break
        results.append(steps)
    assert len(results[0]) == len(results[1])
    for step_a, step_b in zip(*results):
        assert all(equivalent(a, b) for a, b in zip(step_a, step_b))


# --- a flight branched from Python, each branch the flight C++ flies (Simulator::Run) ---------------------------
BRANCH_EPOCH = 3  # s: the epoch the flight is copied at
BRANCH_SEED = 4


def finish(env, action):
    done = env.done
    while not done:
        _, _, done, _, _ = env.step(action)


def comparable(flight):
    return {k: v for k, v in flight.summary().items() if k not in WALL_CLOCK_FIELDS}, flight.actions


def test_a_flight_branched_from_python_flies_each_branch_as_cpp_does():
    scenario = example("nominal.yaml")
    env = uascma.Environment(scenario, record=True)
    env.reset(seed=BRANCH_SEED)
    for _ in range(BRANCH_EPOCH):
        env.step("NoOp")
    snapshot = env.snapshot()
    assert abs(snapshot.time_s - BRANCH_EPOCH) < 1e-9
    finish(env, "NoOp")
    stay = comparable(env.flight())
    observation, info = env.restore(snapshot)
    assert info["time_s"] == snapshot.time_s and env.observation_space.contains(observation)
    env.step("LandASAP")
    finish(env, "NoOp")
    land = comparable(env.flight())
    # Branching again from the same copy flies the same branch.
    env.restore(snapshot)
    finish(env, "NoOp")
    assert comparable(env.flight()) == stay
    # The C++ flights of the same seed: NoOp throughout, and LandASAP at the branch's epoch.
    noop_run = uascma.run(scenario, "noop", seed=BRANCH_SEED, telemetry=False)
    land_run = uascma.run(scenario, lambda inputs: "LandASAP" if round(inputs.time_s) == BRANCH_EPOCH else "NoOp",
                          seed=BRANCH_SEED, telemetry=False)
    assert stay == comparable(noop_run)
    assert land == comparable(land_run)
    assert stay != land  # the branches differ
    # A snapshot of the same flight at the same epoch, taken by another environment, is the same state.
    other = uascma.Environment(scenario)
    other.reset(seed=BRANCH_SEED)
    for _ in range(BRANCH_EPOCH):
        other.step("NoOp")
    assert other.snapshot() == snapshot
