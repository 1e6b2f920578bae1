#!/usr/bin/python3
"""Python overhead of flying uascma from Python (run by `make bench` through scripts/bench.sh).

Times the same 1 Hz-decision flight (examples/nominal.yaml, fixed seed, no telemetry recorded) three ways:
  cpp      uascma.run(scenario, "noop"): the whole flight in C++ (sim::Simulator::Run)
  callable uascma.run(scenario, python_noop): the same flight, the decision module a Python callable
  env      the decision environment stepped from Python (reset, then step(NoOp) until done), when the module
           has one (uascma.Environment)
and prints the fastest and the median of interleaved repetitions, with the overhead of each against cpp. Our target is
at most 20 % for the environment.
"""
import os
import statistics
import sys
import time

import uascma

HERE = os.path.dirname(os.path.abspath(__file__))
SCENARIO = os.path.join(HERE, "..", "examples", "nominal.yaml")
SEED = 1
REPETITIONS = int(os.environ.get("UASCMA_BENCH_REPETITIONS", "9"))


def time_cases(cases):
    """Times every case REPETITIONS times, interleaved (so that a burst of load on the shared machine hits all
    cases alike); returns {name: [seconds, …]}."""
    for fn in cases.values():
        fn()  # warm-up: first-touch allocations, imports
    times = {name: [] for name in cases}
    for _ in range(REPETITIONS):
        for name, fn in cases.items():
            start = time.perf_counter()
            fn()
            times[name].append(time.perf_counter() - start)
    return times


def python_noop(inputs):
    return uascma.CmaAction.NoOp


def main():
    scenario = uascma.load_scenario(SCENARIO)
    reference = uascma.run(scenario, "noop", seed=SEED, telemetry=False)
    cases = {
        "cpp": lambda: uascma.run(scenario, "noop", seed=SEED, telemetry=False),
        "callable": lambda: uascma.run(scenario, python_noop, seed=SEED, telemetry=False),
    }
    if hasattr(uascma, "Environment"):
        def env_flight():
            env = uascma.Environment(scenario)
            env.reset(seed=SEED)
            terminated = truncated = False
            while not (terminated or truncated):
                _, _, terminated, truncated, _ = env.step(uascma.CmaAction.NoOp)
        cases["env"] = env_flight
    times = time_cases(cases)
    print(f"flight: {os.path.basename(SCENARIO)} seed {SEED}, {reference.sim_time_s:.0f} s simulated, "
          f"{reference.outcome}; {REPETITIONS} interleaved repetitions (overhead from the fastest of each)")
    base = min(times["cpp"])
    for name, samples in times.items():
        fastest, median = min(samples), statistics.median(samples)
        print(f"  {name:9s} fastest {fastest * 1e3:8.2f} ms ({reference.sim_time_s / fastest:6.0f}x real time), "
              f"median {median * 1e3:8.2f} ms, overhead {100.0 * (fastest / base - 1.0):+6.1f} %")
    results = times
    if "env" not in results:
        print("  env       (the module has no decision environment in this build)")
    return 0


if __name__ == "__main__":
    sys.exit(main())
