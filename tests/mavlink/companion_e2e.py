#!/usr/bin/env python3
"""The CMA as two processes against the CMA in process (docs/mavlink.md#the-cma-as-a-companion).

Runs `uascma companion` listening on loopback and `uascma sitl SCENARIO --cma external` sending to it, and compares
the vehicle's events with `uascma simulate SCENARIO --json`'s: the same events (the spall, the jam, the isolation, the
speed cap, each emergency plan to the same site, the landing at the same site), each within one decision epoch
(1 s, the scenario's 1 Hz), and every action the in-process CMA took taken by the companion too. Also checks the
companion's decision time against the epoch's wall period at the pace (1 / SPEED s) and that the vehicle kept the pace
over the flight.

usage: companion_e2e.py BUILD_DIR SOURCE_DIR SCENARIO.yaml SPEED
"""
import json
import re
import subprocess
import sys
import time

EPOCH_S = 1.0  # the decision period (§5.4, Fig. 5.15: 1 Hz): the tolerance on each event's time


def kind(what):
    """An event without its figures in parentheses: 'LandPract: emergency plan to roof block 11,2 lot s/6'."""
    return what.split(" (")[0].strip()


def read_port(process, timeout_s=20.0):
    end = time.time() + timeout_s
    while time.time() < end:
        line = process.stdout.readline()
        match = re.match(r"listening on udp:127\.0\.0\.1:(\d+)", line)
        if match:
            return int(match.group(1))
    raise SystemExit("the companion did not say its port")


def main():
    build, source, scenario, speed = sys.argv[1], sys.argv[2], sys.argv[3], float(sys.argv[4])
    uascma = f"{build}/uascma"
    in_process = json.loads(subprocess.run([uascma, "simulate", scenario, "--json"], check=True, cwd=source,
                                           capture_output=True, text=True).stdout)
    companion = subprocess.Popen([uascma, "companion", "--mavlink", "udp:127.0.0.1:0", "--scenario", scenario],
                                 cwd=source, stdout=subprocess.PIPE, text=True)
    port = read_port(companion)
    sitl = subprocess.run([uascma, "sitl", scenario, "--cma", "external", "--mavlink", f"udpout:127.0.0.1:{port}",
                           "--speed", str(speed), "--linger", "1"], cwd=source, capture_output=True, text=True,
                          timeout=3600)
    companion_out, _ = companion.communicate(timeout=60)
    print(sitl.stdout)
    print(companion_out)
    if sitl.returncode != 0 or companion.returncode != 0:
        raise SystemExit(f"sitl exit {sitl.returncode}, companion exit {companion.returncode}: {sitl.stderr}")
    events = []
    for line in sitl.stdout.splitlines():
        match = re.match(r"\s*([0-9.]+) s  (.*)$", line)
        if match:
            events.append((float(match.group(1)), match.group(2)))
    failures = []
    expected = [(e["time_s"], e["what"]) for e in in_process["events"]]
    if len(events) != len(expected):
        failures.append(f"{len(events)} events, in process {len(expected)}")
    for t, what in expected:
        near = [u for u, other in events if kind(other) == kind(what) and abs(u - t) <= EPOCH_S + 0.05]
        if not near:
            failures.append(f"no '{kind(what)}' within {EPOCH_S} s of {t:.2f} s")
    actions = [a["action"] for a in in_process["actions"]]
    # The rows the companion prints: every action taken, and NoOp rows with a note (the mission downloaded, …).
    taken = [action for action in re.findall(r" -> (\w+) ", companion_out) if action != "NoOp"]
    if taken != actions:
        failures.append(f"companion took {taken}, in process {actions}")
    summary = re.search(r"decision time ([0-9.]+) ms mean, ([0-9.]+) ms max", companion_out)
    period_ms = 1000.0 / speed
    if not summary or float(summary.group(2)) > period_ms:
        failures.append(f"decision time above the epoch's wall period {period_ms:.0f} ms: {summary and summary.group(0)}")
    # The pace held over the flight: simulated over wall time within 1 % of SPEED (an epoch's stepping may end after its
    # deadline on a loaded machine, "late" in the summary, and the next catches up).
    pace = re.search(r"s wall \(([0-9.]+)x", sitl.stdout)
    if not pace or float(pace.group(1)) < 0.99 * speed:
        failures.append(f"the vehicle did not keep {speed}x: {pace and pace.group(0)}")
    for failure in failures:
        print("FAIL:", failure)
    return 1 if failures else 0


if __name__ == "__main__":
    sys.exit(main())
