#!/usr/bin/env bash
# Runs every parser's libFuzzer harness (fuzz/, issue 16) for SECONDS each, one after the other, from
# seed corpora assembled here at run time (examples/, the OSM data of ../shared/data/osm when present,
# generated OSM and results-store seeds); nothing of it is committed. Prints executions, coverage (cov)
# and features (ft) per parser, and fails on any crash, hang, leak or out-of-memory, whose input is
# then in BUILD_DIR/fuzz/artifacts/PARSER/. Usage: fuzz.sh [BUILD_DIR [SECONDS [JOBS]]]
# The policy and results-store seeds are written by the tool: $UASCMA_CLI, else the instrumented build's.
# FUZZ_PARSERS="weights_yaml geojson …" runs only those (default: all nine).
set -euo pipefail
cd "$(dirname "$0")/.."
root=$(pwd)
build=${1:-build-fuzz}
seconds=${2:-60}
jobs=${3:-$(nproc)}
shared=${UASCMA_SHARED_DATA:-$root/../shared/data}
launcher=()
if command -v ccache >/dev/null; then launcher=(-DCMAKE_CXX_COMPILER_LAUNCHER=ccache); fi

cmake -S . -B "$build" -DCMAKE_BUILD_TYPE=Release -DCMAKE_CXX_COMPILER=clang++ -DUASCMA_FUZZ=ON \
  -DUASCMA_BUILD_TESTS=OFF -DUASCMA_BUILD_BENCHMARKS=OFF "${launcher[@]}" >/dev/null
parsers=(${FUZZ_PARSERS:-scenario_yaml campaign_yaml weights_yaml policy_json geojson osm_xml osm_pbf sites_csv results_store})
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
  examples/scenario-1.yaml examples/scenario-2.yaml
seed campaign_yaml examples/campaign.yaml
seed weights_yaml examples/cma-weights.yaml
seed geojson "$shared"/osm/*.geojson
seed sites_csv "$shared"/osm/*.csv
mkdir -p "$corpus/osm_xml" "$corpus/osm_pbf" "$corpus/policy_json" "$corpus/results_store"
"$bin/fuzz_osm_seeds" "$corpus/osm_xml" "$corpus/osm_pbf"
# A policy file and a small results store, written by the tool itself (the instrumented build's).
scratch=$(mktemp -d)
trap 'rm -rf "$scratch"' EXIT
export ASAN_OPTIONS=detect_leaks=0  # the seed-making runs of the tool are not what is being fuzzed
"$cli" policy solve --model cma --out "$corpus/policy_json/cma-policy.json" >/dev/null
printf 'runs: 2\nmap: {procedural_seed: 0}\nmission: {distance_m: [20, 40], cruise_speed_mps: [4, 6], cruise_altitude_m: 5, drop_hover_s: 2}\n' \
  >"$scratch/tiny.yaml"
rm -f "$corpus/results_store/tiny.db"  # the seed is rewritten each time (campaign refuses an existing file)
"$cli" campaign "$scratch/tiny.yaml" --policies noop --db "$corpus/results_store/tiny.db" --jobs 1 >/dev/null
unset ASAN_OPTIONS

# Big inputs (the 1.7 MB GeoJSON) are seeds, not mutation targets: -max_len keeps mutations small.
status=0
summary=()
for parser in "${parsers[@]}"; do
  mkdir -p "$artifacts/$parser"
  log=$build/fuzz/$parser.log
  echo "fuzz: $parser for $seconds s"
  if ! "$bin/${parser}_fuzzer" "$corpus/$parser" -max_total_time="$seconds" -timeout=10 -rss_limit_mb=2048 \
       -max_len=65536 -print_final_stats=1 -artifact_prefix="$artifacts/$parser/" >"$log" 2>&1; then
    status=1
    echo "fuzz: $parser FAILED, see $log and $artifacts/$parser/"
  fi
  runs=$(grep -o 'stat::number_of_executed_units: *[0-9]*' "$log" | grep -o '[0-9]*$' || echo "?")
  last=$(grep -E '^#[0-9]+' "$log" | tail -n 1)
  cov=$(grep -o 'cov: [0-9]*' <<<"$last" | grep -o '[0-9]*' || echo "?")
  ft=$(grep -o 'ft: [0-9]*' <<<"$last" | grep -o '[0-9]*' || echo "?")
  summary+=("$(printf '%-14s %10s execs  cov %6s  ft %6s' "$parser" "$runs" "$cov" "$ft")")
done
printf '%s\n' "${summary[@]}"
exit $status
