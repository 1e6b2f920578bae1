#!/usr/bin/env bash
# Runs every parser's libFuzzer harness (fuzz/) for SECONDS each, PARALLEL of them at a time (default
# 1, one after the other), from seed corpora assembled here at run time (examples/, tests/data/missions, the OSM
# data of data/osm, generated OSM, policy, battery-model and results-store seeds); nothing of
# it is committed. Prints executions, coverage (cov) and features (ft) per parser, and fails on any crash, hang,
# leak or out-of-memory, whose input is then in BUILD_DIR/fuzz/artifacts/PARSER/.
# Usage: fuzz.sh [BUILD_DIR [SECONDS [JOBS [PARALLEL]]]]   (JOBS: build threads)
# The seeds that the tool writes come from $UASCMA_CLI, else the instrumented build's CLI.
# Each source is compiled alone (-DUASCMA_UNITY=OFF): the harnesses and their coverage map to single files.
# FUZZ_PARSERS="weights_yaml geojson …" runs only those (default: all thirteen). The fuzzers run at nice 15.
set -euo pipefail
cd "$(dirname "$0")/.."
root=$(pwd)
build=${1:-build-fuzz}
seconds=${2:-60}
jobs=${3:-$(nproc)}
parallel=${4:-1}
osm_data=$root/data/osm
launcher=()
if command -v ccache >/dev/null; then launcher=(-DCMAKE_CXX_COMPILER_LAUNCHER=ccache); fi

cmake -S . -B "$build" -DCMAKE_BUILD_TYPE=Release -DCMAKE_CXX_COMPILER=clang++ -DUASCMA_FUZZ=ON -DUASCMA_UNITY=OFF \
  -DUASCMA_BUILD_TESTS=OFF -DUASCMA_BUILD_BENCHMARKS=OFF -DUASCMA_BUILD_PYTHON=OFF "${launcher[@]}" >/dev/null
parsers=(${FUZZ_PARSERS:-scenario_yaml campaign_yaml weights_yaml policy_json geojson osm_xml osm_pbf sites_csv
  results_store mission_plan mission_wpl battery_model battery_policy cma_transitions mavlink_frame})
targets=(fuzz_osm_seeds)
for parser in "${parsers[@]}"; do targets+=("${parser}_fuzzer"); done
cmake --build "$build" --target "${targets[@]}" -j "$jobs"
cli=${UASCMA_CLI:-}
if [[ -z $cli ]]; then
  cmake --build "$build" --target uascma_cli -j "$jobs"
  cli=$build/uascma
fi

bin=$build/fuzz
corpus=$build/fuzz/corpus
artifacts=$build/fuzz/artifacts
mkdir -p "$corpus" "$artifacts"
seed() {  # seed PARSER FILE...: copy the files that exist into the parser's corpus
  local parser=$1; shift
  mkdir -p "$corpus/$parser"
  for f in "$@"; do if [[ -f $f ]]; then cp "$f" "$corpus/$parser/"; fi; done
}
seed scenario_yaml examples/nominal.yaml examples/poor-battery-long.yaml examples/jam-motor-3.yaml \
  examples/scenario-1.yaml examples/scenario-2.yaml examples/mission-upper-east-side.yaml
seed campaign_yaml examples/campaign.yaml examples/campaign-manhattan.yaml
seed weights_yaml examples/cma-weights.yaml
seed geojson "$osm_data"/*.geojson
seed sites_csv "$osm_data"/*.csv
seed mission_plan examples/missions/*.plan tests/data/missions/*.plan
seed mission_wpl tests/data/missions/*.waypoints
seed mavlink_frame tests/data/mavlink/*.bin
mkdir -p "$corpus/osm_xml" "$corpus/osm_pbf" "$corpus/policy_json" "$corpus/results_store" \
  "$corpus/battery_model" "$corpus/battery_policy"
"$bin/fuzz_osm_seeds" "$corpus/osm_xml" "$corpus/osm_pbf"
# A policy file, a battery model and its policies, and a small results store, written by the tool itself.
scratch=$(mktemp -d)
trap 'rm -rf "$scratch"' EXIT
export ASAN_OPTIONS=detect_leaks=0  # the seed-making runs of the tool are not what is being fuzzed
"$cli" policy solve --model cma --out "$corpus/policy_json/cma-policy.json" >/dev/null
mkdir -p "$corpus/cma_transitions"  # transitions counted from one flight
"$cli" learn transitions --runs 1 --jobs 1 --out "$corpus/cma_transitions/transitions.json" >/dev/null
rm -f "$corpus/battery_model/model.json" "$corpus/battery_policy/policy.json"  # the tool refuses nothing here,
"$cli" battery learn --runs 3 --jobs 1 --out "$corpus/battery_model/model.json" >/dev/null  # but keep them fresh
"$cli" battery solve "$corpus/battery_model/model.json" --out "$corpus/battery_policy/policy.json" >/dev/null
printf 'runs: 2\nmap: {procedural_seed: 0}\nmission: {distance_m: [20, 40], cruise_speed_mps: [4, 6], cruise_altitude_m: 5, drop_hover_s: 2}\n' \
  >"$scratch/tiny.yaml"
rm -f "$corpus/results_store/tiny.db"  # the seed is rewritten each time (campaign refuses an existing file)
"$cli" campaign "$scratch/tiny.yaml" --policies noop --db "$corpus/results_store/tiny.db" --jobs 1 >/dev/null
unset ASAN_OPTIONS

# Big inputs (the 1.7 MB GeoJSON) are seeds, not mutation targets: -max_len keeps mutations small. The battery
# policy file is ~200 kB (18 contexts × 289 states), so its harness gets room for the whole seed.
max_len() { case $1 in battery_policy) echo 262144 ;; *) echo 65536 ;; esac; }
# Any UB report is a crash, except libosmium's known UB in its own headers (scripts/ubsan-suppressions.txt).
export UBSAN_OPTIONS=print_stacktrace=1:halt_on_error=1:suppressions=$root/scripts/ubsan-suppressions.txt
run_one() {  # run_one PARSER: one harness for $seconds s; its log is BUILD_DIR/fuzz/PARSER.log
  local parser=$1
  mkdir -p "$artifacts/$parser"
  echo "fuzz: $parser for $seconds s"
  if ! nice -n 15 "$bin/${parser}_fuzzer" "$corpus/$parser" -max_total_time="$seconds" -timeout=10 \
       -rss_limit_mb=2048 -max_len="$(max_len "$parser")" -print_final_stats=1 \
       -artifact_prefix="$artifacts/$parser/" >"$build/fuzz/$parser.log" 2>&1; then
    echo "fuzz: $parser FAILED, see $build/fuzz/$parser.log and $artifacts/$parser/"
    return 1
  fi
}
status=0
pids=()
for parser in "${parsers[@]}"; do
  run_one "$parser" &
  pids+=($!)
  if ((${#pids[@]} >= parallel)); then
    wait "${pids[0]}" || status=1
    pids=("${pids[@]:1}")
  fi
done
for pid in "${pids[@]}"; do wait "$pid" || status=1; done

printf '%-15s %12s %8s %8s %s\n' parser execs cov ft result
for parser in "${parsers[@]}"; do
  log=$build/fuzz/$parser.log
  runs=$(grep -o 'stat::number_of_executed_units: *[0-9]*' "$log" | grep -o '[0-9]*$' || echo "?")
  last=$(grep -E '^#[0-9]+' "$log" | tail -n 1)
  cov=$(grep -o 'cov: [0-9]*' <<<"$last" | grep -o '[0-9]*' || echo "?")
  ft=$(grep -o 'ft: [0-9]*' <<<"$last" | grep -o '[0-9]*' || echo "?")
  found=$(ls "$artifacts/$parser" | wc -l)
  printf '%-15s %12s %8s %8s %s\n' "$parser" "$runs" "$cov" "$ft" \
    "$(if grep -q 'Done [0-9]* runs' "$log"; then echo clean; else echo "FAILED ($found artifacts)"; fi)"
done
exit $status
