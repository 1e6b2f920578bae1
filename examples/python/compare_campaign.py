#!/usr/bin/python3
"""Run a small Monte Carlo campaign (CMA against NoOp on the same sampled flights) and compare the policies
in pandas.

    PYTHONPATH=build/python /usr/bin/python3 examples/python/compare_campaign.py [--db campaign.db] [--runs 20]

An existing --db is read as it is (e.g. one written by `uascma campaign`); otherwise the campaign of
examples/campaign.yaml is flown with --runs sampled scenarios into it.
"""
import argparse
import os

import pandas as pd

import uascma


def main():
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--db", default="campaign.db")
    parser.add_argument("--runs", type=int, default=20)
    parser.add_argument("--seed", type=int, default=1)
    args = parser.parse_args()

    if not os.path.exists(args.db):
        outcome = uascma.run_campaign(uascma.example_file("campaign.yaml"), args.db, runs=args.runs,
                                      seed=args.seed)
        print(f"flew {outcome['flights_flown']} flights in {outcome['wall_time_s']:.1f} s into {args.db}")
    runs = uascma.read_campaign(args.db)
    print(f"{len(runs)} flights, campaign {runs.attrs['campaign']['name']} (seed {runs.attrs['campaign']['seed']})\n")

    # Failure rate per policy and battery health (Fig. 5.30's comparison).
    print("failure rate by battery health:")
    print(runs.pivot_table(index="battery_health", columns="policy", values="failure", aggfunc="mean")
          .round(3).to_string(), "\n")

    # Outcome shares per policy (Fig. 5.31).
    print("outcomes:")
    print(pd.crosstab(runs["outcome"], runs["policy"], normalize="columns").round(3).to_string(), "\n")

    # Paired comparison: each run_index was flown by every policy on the same scenario.
    paired = runs.pivot(index="run_index", columns="policy", values="failure")
    only_noop = int((paired["noop"] & ~paired["cma"]).sum())
    only_cma = int((paired["cma"] & ~paired["noop"]).sum())
    print(f"paired runs where only NoOp failed: {only_noop}; only CMA failed: {only_cma}")

    # Rewards per epoch (Fig. 5.32) and when CMA first acted.
    print(runs.groupby("policy")[["average_reward", "min_reward"]].mean().round(4).to_string())
    cma = runs[runs["policy"] == "cma"]
    acted = cma.dropna(subset=["first_emergency_action_s"])
    if len(acted):
        print("\nCMA's first emergency actions:")
        print(acted["first_emergency_action"].value_counts().to_string())


if __name__ == "__main__":
    main()
