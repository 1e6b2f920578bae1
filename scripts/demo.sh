#!/usr/bin/env bash
# The main job on the built-in defaults: solve the contingency-management policy and show it.
set -euo pipefail
build=${1:-build}
out="$build/demo"
mkdir -p "$out"
"$build/uascma" policy solve --model cma --out "$out/cma-policy.json"
echo
"$build/uascma" policy show "$out/cma-policy.json" --plot "$out/cma-policy.png"
echo
echo "quadrant figure: $out/cma-policy.png"
