#!/usr/bin/env bash
# The interoperability test: ArduPilot's node-mavlink (npm, test-only, installed into BUILD_DIR/node-interop) as the
# ground station of `uascma sitl` on loopback. Usage: run-interop.sh BUILD_DIR SOURCE_DIR
# For each mission file of examples/missions, two sitl runs at --speed 50, each with one client (interop.mjs) that
# parses every frame, uploads and downloads the mission, arms, starts and reads the telemetry: examples/scenario-1.yaml
# --wait-for-start (the scenario's plan and its fault), and the example scenario that flies the file (its map)
# --wait-for-mission (the uploaded mission flown, its items reached).
set -euo pipefail
build=$1
source=$2
# Skipped (CTest's SKIP_RETURN_CODE, tests/CMakeLists.txt) until Node.js is installed.
if ! command -v node >/dev/null || ! command -v npm >/dev/null; then
  echo "interop: skipped: node and npm are not on the PATH (scripts/install-deps.sh test-tools)"
  exit 77
fi
prefix=$build/node-interop
if [[ ! -d $prefix/node_modules/node-mavlink ]]; then
  mkdir -p "$prefix"
  cp "$source/tests/mavlink/node/package.json" "$prefix/package.json"
  (cd "$prefix" && npm install --no-audit --no-fund --loglevel=error >/dev/null)
fi
cp "$source/tests/mavlink/node/interop.mjs" "$prefix/interop.mjs"
status=0
# One sitl run and one client: run_pair SCENARIO MISSION MODE SITL_FLAG
run_pair() {
  local log
  log=$(mktemp)
  "$build/uascma" sitl "$1" --mavlink udp:127.0.0.1:0 --speed 50 --linger 3 "$4" >"$log" 2>&1 &
  local sitl=$!
  local port=""
  for _ in $(seq 1 100); do
    port=$(sed -n 's/^listening on udp:127.0.0.1:\([0-9]*\)$/\1/p' "$log")
    [[ -n $port ]] && break
    sleep 0.1
  done
  if [[ -z $port ]]; then
    echo "interop: sitl did not start"; cat "$log"; kill "$sitl" 2>/dev/null || true; exit 1
  fi
  if ! node "$prefix/interop.mjs" "$port" "$2" "$3"; then
    status=1
    kill "$sitl" 2>/dev/null || true  # a vehicle still waiting on the ground for the client's start
  fi
  wait "$sitl" || status=1
  tail -n 1 "$log"
  rm -f "$log"
}
for mission in "$source"/examples/missions/*.plan; do
  # The scenario's plan, with its fault: the CMA's events seen.
  run_pair "$source/examples/scenario-1.yaml" "$mission" start --wait-for-start
  # The uploaded mission flown, over the map of the example scenario that flies this file (its frame and buildings).
  scenario=$(grep -l "file: missions/$(basename "$mission")" "$source"/examples/*.yaml | head -n 1)
  if [[ -z $scenario ]]; then
    echo "interop: no example scenario flies $(basename "$mission") (mission: {file: missions/...})"; status=1
    continue
  fi
  run_pair "$scenario" "$mission" mission --wait-for-mission
done
exit $status
