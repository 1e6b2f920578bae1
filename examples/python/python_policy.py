#!/usr/bin/python3
"""A hand-written decision policy (a Python function) flown through the decision environment, Gym-style.

    PYTHONPATH=build/python /usr/bin/python3 examples/python/python_policy.py [SCENARIO.yaml] [--seed S]

The policy sees each 1 Hz observation (the CMA state and the EOD, RUL and margins behind it) and returns a CMA
action. This one is a simple rule: land at a practical site as soon as a motor is spalled or jammed and the
remaining flight no longer fits in the RUL, or the battery's reach margin drops below 0.2; otherwise fly on.
It is compared with the solved CMA policy and with NoOp on the same flight (same seed).
"""
import argparse
import math

import uascma


def cautious(state_index, info):
    """Return a CMA action for an epoch: the state index and the uascma.Observation behind it."""
    observation = info["observation"]
    if observation.flight_status != uascma.FlightStatus.N:
        return "NoOp"  # already landing: keep the emergency plan
    motor_trouble = observation.state.mh != uascma.MotorHealth.NF
    rul_too_short = math.isfinite(observation.rul_s) and observation.rul_s < observation.flight_time_remaining_s
    if (motor_trouble and rul_too_short) or observation.reach_margin < 0.2:
        return "LandPract"
    return "NoOp"


def episode(env, policy, seed):
    """Flies one flight (Gymnasium's loop); returns the undiscounted return and the outcome."""
    observation, info = env.reset(seed=seed)
    total, terminated, truncated = 0.0, False, False
    while not (terminated or truncated):
        observation, reward, terminated, truncated, info = env.step(policy(observation, info))
        total += reward
    return total, info["outcome"]


def main():
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("scenario", nargs="?", default=uascma.example_file("jam-motor-3.yaml"))
    parser.add_argument("--seed", type=int, default=None, help="default: the scenario's seed")
    args = parser.parse_args()

    cma = uascma.solve_cma()
    policies = {
        "cautious (Python)": cautious,
        "cma (solved MDP)": lambda state, info: cma.policy.action[state],
        "noop": lambda state, info: "NoOp",
    }
    env = uascma.Environment(args.scenario, record=True)
    # The same flight for every policy: the given seed, else the scenario's.
    seed = args.seed if args.seed is not None else uascma.load_scenario(args.scenario).seed
    for name, policy in policies.items():
        total, outcome = episode(env, policy, seed)
        flight = env.flight(name)
        print(f"{name:18s} {outcome:18s} after {flight.sim_time_s:6.1f} s, return {total:7.3f}, "
              f"actions {flight.actions}")


if __name__ == "__main__":
    main()
