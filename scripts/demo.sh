#!/usr/bin/env bash
# The main job on the built-in defaults: solve and show the contingency-management policy, fly the
# dissertation's Scenario I over the procedural city and draw it, then run a Monte Carlo campaign of NoOp, CMA and
# the vehicle-level CMA (docs/cma-vehicle.md; 450 flights, 150 runs each flown by the three) and print the table.
set -euo pipefail
build=${1:-build}
out="$build/demo"
mkdir -p "$out"
echo "== CMA policy (dissertation §5.3.2)"
"$build/uascma" policy solve --model cma --out "$out/cma-policy.json"
"$build/uascma" policy show "$out/cma-policy.json" --plot "$out/cma-policy.png"
echo
echo "== Scenario I (§5.5.1)"
"$build/uascma" simulate examples/scenario-1.yaml --out "$out/scenario-1"
"$build/uascma" plot "$out/scenario-1"
echo
echo "== Monte Carlo campaign: NoOp, CMA (§5.5.3) and the vehicle-level CMA (docs/cma-vehicle.md)"
rm -f "$out/campaign.db"
"$build/uascma" campaign examples/campaign.yaml --runs 150 --policies noop,cma,cma-vehicle --seed 1 --db "$out/campaign.db"
"$build/uascma" report "$out/campaign.db" --plots "$out/campaign-plots" > /dev/null
echo
echo "figures: $out/cma-policy.png, $out/scenario-1/*.png, $out/campaign-plots/"
