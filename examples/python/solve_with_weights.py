#!/usr/bin/python3
"""Solve the CMA MDP with changed reward weights, see which decisions change, and fly both policies.

    PYTHONPATH=build/python /usr/bin/python3 examples/python/solve_with_weights.py [--weight RM --value 0.4]

The swept weight takes the value and the others are renormalised to keep the sum at one (Fig. 5.10, eq. 5.22).
"""
import argparse

import pandas as pd

import uascma


def main():
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--weight", default="RM", help="one of " + ", ".join(uascma.CmaWeights.names()))
    parser.add_argument("--value", type=float, default=0.4)
    parser.add_argument("--out", default="tuned-policy.json")
    parser.add_argument("--scenario", default=uascma.example_file("jam-motor-3.yaml"))
    args = parser.parse_args()

    default = uascma.solve_cma()
    weights = uascma.CmaWeights().renormalised(args.weight, args.value)
    tuned = uascma.solve_cma(weights)
    print("weights:", {k: round(v, 4) for k, v in weights.as_dict().items()})
    print("default:", default.summary.brief_report())
    print("tuned:  ", tuned.summary.brief_report())

    # Fig. 5.9's quadrant view of both, side by side; the cells whose action changed.
    both = pd.DataFrame(default.quadrants()).merge(pd.DataFrame(tuned.quadrants()),
                                                   on=["FS", "MH", "BH", "quadrant", "state"],
                                                   suffixes=("_default", "_tuned"))
    changed = both[both["action_default"] != both["action_tuned"]]
    print(f"\n{len(changed)} of {len(both)} quadrant cells change action with {args.weight} = {args.value}:")
    print(changed[["state", "action_default", "action_tuned"]].to_string(index=False))

    tuned.save(args.out)  # the same file `uascma policy solve --weights …` writes
    print("\nwrote", args.out)
    for name, policy in (("default", default), ("tuned", uascma.load_policy(args.out))):
        flight = uascma.run(args.scenario, policy, telemetry=False)
        print(f"{name:8s}: {flight.outcome:18s} after {flight.sim_time_s:6.1f} s, actions {flight.actions}")


if __name__ == "__main__":
    main()
