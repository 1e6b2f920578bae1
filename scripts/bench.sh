#!/usr/bin/env bash
# Runs every benchmark under build/bench and prints its figures.
set -euo pipefail
build=${1:-build}
for bench in "$build"/bench/*_bench; do
  echo "== $(basename "$bench")"
  "$bench" --benchmark_min_time=0.2
done
# The Python module's overhead (bench/python_env_bench.py), when the build has the module.
if [[ -f "$build/python/uascma/__init__.py" ]]; then
  echo "== python_env_bench"
  PYTHONPATH="$build/python" /usr/bin/python3 "$(dirname "$0")/../bench/python_env_bench.py"
fi
# Instructions per 200 Hz GNC step on examples/nominal.yaml (bench/step_instructions.sh, callgrind).
echo "== step_instructions"
bash "$(dirname "$0")/../bench/step_instructions.sh" "$build"
# The same count under every pack and Dryden rate, and with parts of the step removed: the floor of one flight's step
# (bench/step_floor.sh, ~2 CPU minutes; STEP_FLOOR_SKIP=1 skips it).
if [[ "${STEP_FLOOR_SKIP:-0}" != 1 ]]; then
  echo "== step_floor (STEP_FLOOR_SKIP=1 skips it)"
  bash "$(dirname "$0")/../bench/step_floor.sh" "$build"
fi
# The 10,000-flight campaign (with and without lockstep), battery learning and Q-learning as timed CLI runs
# (bench/headline.sh; ~13 CPU minutes).
if [[ "${HEADLINE_SKIP:-0}" != 1 ]]; then
  echo "== headline (HEADLINE_SKIP=1 skips it)"
  bash "$(dirname "$0")/../bench/headline.sh" "$build"
fi
# Start-up of `uascma` and of `import uascma` (bench/startup_bench.py).
echo "== startup_bench"
/usr/bin/python3 "$(dirname "$0")/../bench/startup_bench.py" "$build"
