#!/usr/bin/env bash
# The throughput figures, as timed runs of the command-line tool (not unit tests): the 10,000-flight
# default campaign (examples/campaign.yaml, 5,000 runs x 2 policies; then again one run at a time per thread, the
# lockstep's ratio on this machine), battery learning from 5,000 flights and
# 10,000 Q-learning episodes, each on 2 threads. Prints wall and CPU seconds (user + sys, all threads), the load
# average before and after (a loaded machine stretches the wall time, not the CPU time) and, for the campaign,
# flights per CPU-second. The targets: <= 120 s, <= 60 s and <= 120 s of wall time on 2 idle cores.
#   bash bench/headline.sh [BUILD_DIR]      (~13 CPU minutes; HEADLINE_SKIP=1 skips it in `make bench`)
set -euo pipefail
build=${1:-build}
cli="$(cd "$build" && pwd)/uascma"
root="$(cd "$(dirname "$0")/.." && pwd)"
work="$(mktemp -d)"
trap 'rm -rf "$work"' EXIT
load() { cut -d' ' -f1-3 /proc/loadavg; }

timed() {  # timed LABEL UNITS COMMAND...: runs it, prints "LABEL: W s wall, C CPU s (load before -> after)"
  local label=$1 units=$2
  shift 2
  local before
  before=$(load)
  /usr/bin/time -f "%e %U %S" -o "$work/time" "$@" > /dev/null 2> "$work/stderr" || {
    cat "$work/stderr" >&2
    return 1
  }
  read -r wall user sys < "$work/time"
  python3 - "$label" "$units" "$wall" "$user" "$sys" "$before" "$(load)" <<'EOF'
import sys
label, units, wall, user, sys_s, before, after = sys.argv[1:]
cpu = float(user) + float(sys_s)
line = f"{label}: {float(wall):.1f} s wall, {cpu:.1f} CPU s"
if float(units) > 0:
    line += f", {float(units) / cpu:.1f} per CPU-second"
print(f"{line} (load {before} -> {after})")
EOF
}

cd "$root"
timed "10,000-flight default campaign (5,000 runs x 2 policies, --jobs 2)" 10000 \
  "$cli" campaign examples/campaign.yaml --runs 5000 --seed 1 --jobs 2 --db "$work/campaign.db"
# The same campaign one run at a time per thread (no lockstep): the lanes' gain on this machine.
timed "the same, one run at a time (--runs-in-flight 1)" 10000 \
  "$cli" campaign examples/campaign.yaml --runs 5000 --seed 1 --jobs 2 --runs-in-flight 1 --db "$work/campaign-alone.db"
timed "battery learning, 5,000 flights (--jobs 2)" 5000 \
  "$cli" battery learn --runs 5000 --seed 1 --jobs 2 --out "$work/battery-model.json"
timed "Q-learning, 10,000 episodes (--jobs 2)" 10000 \
  "$cli" learn q --episodes 10000 --seed 1 --jobs 2 --out "$work/q-policy.json"
