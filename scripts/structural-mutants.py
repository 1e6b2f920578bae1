#!/usr/bin/env python3
"""Structural mutants of uascma's own input files, run through the CLI: every run must end with exit 0 or 2, and
every exit 2 must print one line naming the mutant's file.

    scripts/structural-mutants.py build/apps/uascma/uascma [--out FOLDER] [--timeout S]

Kinds of mutant, each applied to each seed file:
  depth      an array or mapping nested 100,000 deep where a value was
  size       a 10 MB scalar where a value was
  encoding   a byte that is not UTF-8, control characters, a UTF-16 byte order mark, CR-only line endings
  duplicates a key (or CSV column) given twice, a second YAML document
Seed files: the examples' scenario, campaign and weights YAML, a solved policy, learned transitions, the test
missions (.plan, .waypoints) and a landing-site CSV. Prints one line per mutant that broke the rule and a tally;
exit code 1 when any did.
"""
import argparse
import json
import os
import subprocess
import sys
import tempfile

ROOT = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))
EXAMPLES = os.path.join(ROOT, "examples")
MISSIONS = os.path.join(ROOT, "tests", "data", "missions")
DEEP = 100_000
BIG = 10 * 1000 * 1000

SITES_CSV = "osm_id,lat,lon,alt,risk,radius\n1,40.7400,-73.9900,0,0.2,3\n2,40.7410,-73.9880,12,0.4,5\n"


def yaml_mutants(text):
    lines = text.splitlines(keepends=True)
    first_value = next(i for i, line in enumerate(lines) if ": " in line and not line.startswith("#"))
    key = lines[first_value].split(":")[0]
    head, tail = lines[:first_value], lines[first_value + 1:]
    return {
        "depth": "".join(head) + key + ": " + "[" * DEEP + "]" * DEEP + "\n" + "".join(tail),
        "size": "".join(head) + key + ": \"" + "a" * BIG + "\"\n" + "".join(tail),
        "encoding-byte": "".join(head) + key + ": \"a\udcff\"\n" + "".join(tail),  # the byte 0xFF (surrogateescape)
        "encoding-control": "".join(head) + key + ": \"\x1b[2J\"\n" + "".join(tail),
        "encoding-cr": text.replace("\n", "\r"),
        "duplicates-key": text + "\n" + lines[first_value],
        "duplicates-document": text + "\n---\n" + text,
    }


def json_mutants(text):
    document = json.loads(text)
    key = next(iter(document)) if isinstance(document, dict) else None
    out = {}
    if key is not None:
        nested = dict(document)
        nested[key] = None
        dumped = json.dumps(nested)
        marker = json.dumps(key) + ": null"
        out["depth"] = dumped.replace(marker, json.dumps(key) + ": " + "[" * DEEP + "]" * DEEP, 1)
        big = dict(document)
        big[key] = "a" * BIG
        out["size"] = json.dumps(big)
        out["duplicates-key"] = "{" + json.dumps(key) + ": 1, " + text.strip()[1:]
    out["encoding-control"] = text.replace("\"", "\"\x01", 1)
    out["encoding-cr"] = text.replace("\n", "\r")
    out["number-overflow"] = text.replace("0", "1e999", 1) if "0" in text else text + "1e999"
    return out


def csv_mutants(text):
    header, rest = text.split("\n", 1)
    return {
        "size": header + "\n" + "1," + "9" * BIG + ",-73.99,0,0.2,3\n",
        "encoding-byte": header + "\n1,40.74,-73.99,\x1b[2J,0.2,3\n",
        "encoding-cr": text.replace("\n", "\r"),
        "duplicates-column": header + ",lat\n" + "\n".join(line + ",41" for line in rest.splitlines()) + "\n",
    }


def wpl_mutants(text):
    return {
        "size": text + "9" * BIG + "\n",
        "encoding-control": text.replace("\t", "\t\x1b[2J", 1),
        "encoding-cr": text.replace("\n", "\r"),
    }


def write(path, text):
    data = text.encode("utf-8", "surrogateescape") if isinstance(text, str) else text
    with open(path, "wb") as f:
        f.write(data)


def run(cli, arguments, timeout):
    try:
        result = subprocess.run([cli] + arguments, capture_output=True, text=True, errors="replace", timeout=timeout)
    except subprocess.TimeoutExpired:
        return None, ""
    return result.returncode, result.stderr


def seeds(cli, folder):
    """(kind, seed file text, command builder) for each seed."""
    policy = os.path.join(folder, "seed-policy.json")
    transitions = os.path.join(folder, "seed-transitions.json")
    subprocess.run([cli, "policy", "solve", "--out", policy], check=True, capture_output=True)
    subprocess.run([cli, "learn", "transitions", "--runs", "1", "--out", transitions], check=True, capture_output=True)
    nominal = os.path.join(EXAMPLES, "nominal.yaml")
    read = lambda path: open(path, encoding="utf-8").read()
    return [
        ("scenario.yaml", yaml_mutants(read(nominal)), lambda f: ["simulate", f, "--out", f + ".out"]),
        ("campaign.yaml", yaml_mutants(read(os.path.join(EXAMPLES, "campaign.yaml"))),
         lambda f: ["map", "coverage", f, "--runs", "1"]),
        ("weights.yaml", yaml_mutants(read(os.path.join(EXAMPLES, "cma-weights.yaml"))),
         lambda f: ["policy", "solve", "--weights", f, "--out", f + ".out"]),
        ("policy.json", json_mutants(read(policy)), lambda f: ["simulate", nominal, "--policy", f]),
        ("transitions.json", json_mutants(read(transitions)),
         lambda f: ["policy", "solve", "--transitions", f, "--out", f + ".out"]),
        ("mission.plan", json_mutants(read(os.path.join(MISSIONS, "delivery_loiter.plan"))),
         lambda f: ["simulate", nominal, "--mission", f]),
        ("mission.waypoints", wpl_mutants(read(os.path.join(MISSIONS, "survey.waypoints"))),
         lambda f: ["simulate", nominal, "--mission", f]),
        ("sites.csv", csv_mutants(SITES_CSV), lambda f: ["map", "info", "--sites", f]),
    ]


def main():
    parser = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    parser.add_argument("cli", help="the uascma binary")
    parser.add_argument("--out", help="keep the mutants in this folder (default: a temporary one)")
    parser.add_argument("--timeout", type=float, default=120.0, help="seconds per run (default 120)")
    args = parser.parse_args()
    folder = args.out or tempfile.mkdtemp(prefix="uascma-mutants-")
    os.makedirs(folder, exist_ok=True)
    tally = {}
    broken = 0
    for name, mutants, command in seeds(os.path.abspath(args.cli), folder):
        for kind, text in mutants.items():
            path = os.path.join(folder, kind + "-" + name)
            write(path, text)
            code, err = run(args.cli, command(path), args.timeout)
            lines = [line for line in err.splitlines() if not line.startswith("uascma: warning")]
            ok = code == 0 or (code == 2 and len(lines) == 1 and path in lines[0])
            tally[code] = tally.get(code, 0) + 1
            if not ok:
                broken += 1
                print(f"BROKEN {path}: exit {code}: {err.strip()[:300]!r}")
    print(f"{sum(tally.values())} mutants: " + ", ".join(f"exit {code}: {n}" for code, n in sorted(tally.items(), key=str)))
    return 1 if broken else 0


if __name__ == "__main__":
    sys.exit(main())
