#!/usr/bin/env bash
# Instructions per 200 Hz GNC step: callgrind counts the instructions of `Simulator::Run` only (set-up,
# parsing and output excluded) while flying examples/nominal.yaml, and divides by the steps flown, the --json
# summary's sim_time_s times the GNC rate (200 Hz in that scenario). Instruction counts do not depend on the machine's
# load, so this figure is comparable between runs where a wall time is not. Another scenario (SCENARIO, a path from
# the repository's root or an absolute one) is counted the same way: bench/step_floor.sh does that for its variants.
#   bash bench/step_instructions.sh [BUILD_DIR] [SCENARIO]
set -euo pipefail
build="$(cd "${1:-build}" && pwd)"
here="$(cd "$(dirname "$0")/.." && pwd)"
scenario="${2:-examples/nominal.yaml}"
if ! command -v valgrind > /dev/null; then
  echo "instructions per 200 Hz step: skipped (valgrind is not installed: bash scripts/install-deps.sh test-tools)"
  exit 0
fi
work="$(mktemp -d)"
trap 'rm -rf "$work"' EXIT
cd "$here"
valgrind --tool=callgrind --toggle-collect='uascma::sim::Simulator::Run*' --callgrind-out-file="$work/callgrind.out" \
  "$build/uascma" simulate "$scenario" --json > "$work/summary.json" 2> "$work/valgrind.log"
python3 - "$work/callgrind.out" "$work/summary.json" <<'PY'
import json, sys
totals = None
for line in open(sys.argv[1]):
    if line.startswith(("totals:", "summary:")):
        totals = int(line.split()[1])
summary = json.load(open(sys.argv[2]))
steps = round(summary["sim_time_s"] * 200)
print(f"instructions per 200 Hz step: {totals / steps:.0f} ({totals:,} instructions in Simulator::Run, {steps:,} steps)")
PY
