"""The decision environment (sim::DecisionEnvironment) stepped from Python, Gym-style."""
import math

import numpy as np
import pytest

import uascma
from conftest import example

WALL_CLOCK_FIELDS = ("wall_time_s", "realtime_factor", "policy")


def fly(env, decide, seed=None):
    """Steps a flight to its end; returns the observations, rewards and the last info."""
    observation = env.reset(seed)
    observations, rewards, info = [observation], [], None
    done = False
    while not done:
        observation, reward, done, info = env.step(decide(observation))
        observations.append(observation)
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
    env = uascma.Environment(example("nominal.yaml"))
    with pytest.raises(uascma.InputError, match="Reset"):
        env.step("NoOp")
    env.reset()
    with pytest.raises(uascma.InputError, match="action"):
        env.step("Hover")
    while not env.done:
        env.step("NoOp")
    with pytest.raises(uascma.InputError, match="ended"):
        env.step("NoOp")
