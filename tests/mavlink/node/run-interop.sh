#!/usr/bin/env bash
# The interoperability test: ArduPilot's node-mavlink (npm, test-only, installed into BUILD_DIR/node-interop) as the
# ground station of `uascma sitl` on loopback. Usage: run-interop.sh BUILD_DIR SOURCE_DIR
# For each mission file of examples/missions, one sitl run of examples/scenario-1.yaml at --speed 50, waiting for the
# client's ARM and MISSION_START, and one client
# (interop.mjs) that parses every frame, uploads and downloads the mission, arms, starts it and reads the telemetry.
set -euo pipefail
build=$1
source=$2
prefix=$build/node-interop
if [[ ! -d $prefix/node_modules/node-mavlink ]]; then
  mkdir -p "$prefix"
  cp "$source/tests/mavlink/node/package.json" "$prefix/package.json"
  (cd "$prefix" && npm install --no-audit --no-fund --loglevel=error >/dev/null)
fi
cp "$source/tests/mavlink/node/interop.mjs" "$prefix/interop.mjs"
status=0
for mission in "$source"/examples/missions/*.plan; do
  log=$(mktemp)
  "$build/uascma" sitl "$source/examples/scenario-1.yaml" --mavlink udp:127.0.0.1:0 --speed 50 --linger 3 --wait-for-start >"$log" 2>&1 &
  sitl=$!
  port=""
  for _ in $(seq 1 100); do
    port=$(sed -n 's/^listening on udp:127.0.0.1:\([0-9]*\)$/\1/p' "$log")
    [[ -n $port ]] && break
    sleep 0.1
  done
  if [[ -z $port ]]; then
    echo "interop: sitl did not start"; cat "$log"; kill "$sitl" 2>/dev/null || true; exit 1
  fi
  if ! node "$prefix/interop.mjs" "$port" "$mission"; then status=1; fi
  wait "$sitl" || status=1
  tail -n 1 "$log"
  rm -f "$log"
done
exit $status
