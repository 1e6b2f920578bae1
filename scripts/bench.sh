#!/usr/bin/env bash
# Runs every benchmark under build/bench and prints its figures.
set -euo pipefail
build=${1:-build}
for bench in "$build"/bench/*_bench; do
  echo "== $(basename "$bench")"
  "$bench" --benchmark_min_time=0.2
done
