#!/usr/bin/env bash
# Times a dissertation-size campaign (§5.5: 465 runs x {cma, noop} = 930 flights) with the CLI:
# 1 and 2 threads in one process, then 1, 2 (and 3, oversubscribed) MPI ranks of one thread each.
# Prints the wall time of each and the speed-up over one thread.
#   bash bench/campaign_scaling.sh [BUILD_DIR] [RUNS] [CAMPAIGN.yaml]
set -euo pipefail
build=${1:-build}
runs=${2:-465}
here=$(cd "$(dirname "$0")/.." && pwd)
config=${3:-$here/examples/campaign.yaml}
uascma=$build/uascma
scratch=$(mktemp -d)
trap 'rm -rf "$scratch"' EXIT

wall() {  # wall seconds of a command
  local start end
  start=$(date +%s.%N)
  "$@" >"$scratch/out" 2>"$scratch/err" || { cat "$scratch/err" >&2; return 1; }
  end=$(date +%s.%N)
  awk -v a="$start" -v b="$end" 'BEGIN { printf "%.3f", b - a }'
}

echo "campaign: $config, $runs runs x 2 policies = $((2 * runs)) flights, $(nproc) cores"
base=""
report() {  # label seconds
  local speedup="1.00"
  [[ -n $base ]] && speedup=$(awk -v a="$base" -v b="$2" 'BEGIN { printf "%.2f", a / b }')
  printf "%-28s %8.1f s   %6.1f flights/s   speed-up %s\n" "$1" "$2" \
    "$(awk -v n="$runs" -v t="$2" 'BEGIN { printf "%.1f", 2 * n / t }')" "$speedup"
}
t=$(wall "$uascma" campaign "$config" --runs "$runs" --db "$scratch/j1.db" --jobs 1); base=$t
report "1 process x 1 thread" "$t"
t=$(wall "$uascma" campaign "$config" --runs "$runs" --db "$scratch/j2.db" --jobs 2)
report "1 process x 2 threads" "$t"
if command -v mpirun >/dev/null 2>&1; then
  for ranks in 1 2 3; do
    t=$(wall mpirun --allow-run-as-root --oversubscribe -n "$ranks" "$uascma" campaign "$config" --runs "$runs" \
      --db "$scratch/mpi$ranks.db" --jobs 1)
    report "mpirun -n $ranks x 1 thread" "$t"
  done
fi
# The rows are the same whichever way the campaign ran (wall_time_s aside).
cols="run_index, policy, outcome, sim_time_s, average_reward, min_reward, min_cell_voltage_v"
for db in "$scratch"/*.db; do
  if command -v sqlite3 >/dev/null 2>&1; then
    sqlite3 "$db" "select $cols from runs order by run_index, policy" | md5sum | sed "s|-|$(basename "$db")|"
  fi
done
"$uascma" report "$scratch/j2.db"
