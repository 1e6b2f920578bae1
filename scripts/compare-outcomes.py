#!/usr/bin/env python3
"""Compare two campaign databases flight by flight and print every difference.

    python3 scripts/compare-outcomes.py BEFORE.db AFTER.db [--time-tol S] [--energy-tol WH] [--all]

Flights are matched by flight_id (the campaign's (run_index, policy) numbering; both databases must hold the same
flights of one campaign, e.g. `uascma campaign examples/campaign.yaml --seed 1 --db X` from two builds). For each
flight the script compares
  - outcome, failure and reason (a changed outcome is always listed),
  - sim_time_s (the end of the flight: landing, crash or time limit), isolation_time_s, jam_time_s and
    first_emergency_action_s / first_emergency_action (when the CMA first acted),
  - the actions taken (num_actions, actions),
  - energy_wh and min_cell_voltage_v,
and, with --all, every other column but wall_time_s and campaign_hash.
A time difference is listed when it exceeds --time-tol seconds (default 0: every difference), an energy difference
when it exceeds --energy-tol W·h (default 0). Prints one line per differing field of a flight, then a summary:
flights compared, flights with a changed outcome, the largest time and energy differences. Exit status 0 when
nothing differs beyond the tolerances, 1 when something does, 2 on bad input.
"""

import argparse
import math
import sqlite3
import sys

TIME_COLUMNS = ["sim_time_s", "isolation_time_s", "jam_time_s", "first_emergency_action_s"]
ENERGY_COLUMNS = ["energy_wh"]
VOLTAGE_COLUMNS = ["min_cell_voltage_v"]
OUTCOME_COLUMNS = ["outcome", "failure", "reason", "first_emergency_action", "num_actions", "actions"]
SKIPPED = {"wall_time_s", "campaign_hash", "flight_id"}


def load(path):
    try:
        db = sqlite3.connect(f"file:{path}?mode=ro", uri=True)
        db.row_factory = sqlite3.Row
        rows = db.execute("SELECT * FROM runs ORDER BY flight_id").fetchall()
    except sqlite3.Error as error:
        sys.exit(f"compare-outcomes: {path}: {error}")
    flights = {}
    for row in rows:
        flights[row["flight_id"]] = dict(row)
    return flights


def numeric_difference(a, b):
    """|a - b|, +inf when exactly one is NULL, 0 when both are."""
    if a is None and b is None:
        return 0.0
    if a is None or b is None:
        return math.inf
    return abs(float(a) - float(b))


def describe(row):
    return f"flight {row['flight_id']} (run {row['run_index']}, {row['policy']}, {row['battery_health']})"


def compare(before, after, args):
    columns = [c for c in next(iter(before.values())).keys() if c not in SKIPPED] if before else []
    lines = []
    outcome_changes = 0
    largest = {c: (0.0, None) for c in TIME_COLUMNS + ENERGY_COLUMNS + VOLTAGE_COLUMNS}
    for flight_id in sorted(set(before) | set(after)):
        if flight_id not in after:
            lines.append(f"flight {flight_id}: only in the first database")
            continue
        if flight_id not in before:
            lines.append(f"flight {flight_id}: only in the second database")
            continue
        a, b = before[flight_id], after[flight_id]
        name = describe(a)
        if a["outcome"] != b["outcome"]:
            outcome_changes += 1
        for column in OUTCOME_COLUMNS:
            if a[column] != b[column]:
                lines.append(f"{name}: {column} {a[column]!r} -> {b[column]!r}")
        for column, tolerance in [(c, args.time_tol) for c in TIME_COLUMNS] + [
            (c, args.energy_tol) for c in ENERGY_COLUMNS
        ] + [(c, 0.0) for c in VOLTAGE_COLUMNS]:
            difference = numeric_difference(a[column], b[column])
            if difference > largest[column][0]:
                largest[column] = (difference, flight_id)
            if difference > tolerance:
                lines.append(f"{name}: {column} {a[column]} -> {b[column]} (difference {difference:.6g})")
        if args.all:
            checked = set(OUTCOME_COLUMNS + TIME_COLUMNS + ENERGY_COLUMNS + VOLTAGE_COLUMNS)
            for column in columns:
                if column not in checked and a.get(column) != b.get(column):
                    lines.append(f"{name}: {column} {a.get(column)!r} -> {b.get(column)!r}")
    return lines, outcome_changes, largest


def main():
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("before")
    parser.add_argument("after")
    parser.add_argument("--time-tol", type=float, default=0.0, help="seconds; list time differences above this")
    parser.add_argument("--energy-tol", type=float, default=0.0, help="W·h; list energy differences above this")
    parser.add_argument("--all", action="store_true", help="also compare every other column (but wall_time_s)")
    args = parser.parse_args()
    if args.time_tol < 0 or args.energy_tol < 0:
        parser.error("tolerances are >= 0")
    before, after = load(args.before), load(args.after)
    if not before or not after:
        print("compare-outcomes: a database holds no runs", file=sys.stderr)
        return 2
    lines, outcome_changes, largest = compare(before, after, args)
    for line in lines:
        print(line)
    print(f"compared {len(set(before) & set(after))} flights ({len(before)} and {len(after)} rows): "
          f"{outcome_changes} outcome changes, {len(lines)} differences listed")
    for column, (difference, flight_id) in largest.items():
        where = f" (flight {flight_id})" if flight_id is not None else ""
        print(f"  largest {column} difference: {difference:.6g}{where}")
    return 1 if lines else 0


if __name__ == "__main__":
    sys.exit(main())
