#!/usr/bin/env bash
# From bench data to identified and validated models (docs/identification.md):
#   a cell from NASA's B0005 (fit on discharge cycle 1, validated on cycle 2),
#   a motor-propeller pair from its 2S and 3S thrust-stand step tests (motor g, propeller 8; validated on its 3S
#   file after a fit on the 2S file alone, and cross-validated leaving one step out when fitted on both);
#   then the vehicle file of this folder (vehicle.yaml) with these two models, flown in a scenario and a campaign
#   (docs/identification.md#vehicle-file).
# Each identification and validation draws its figure into OUT (docs/identification.md#figures): cell-fit.png,
# cell-validation.png (Fig. 3.5), prop-fit.png (Fig. 2.10), prop-validation.png (Fig. 2.11).
# Usage: examples/identify/run.sh [UASCMA] [OUT]   (defaults: build/uascma, a temporary folder)
set -euo pipefail
here="$(cd "$(dirname "$0")" && pwd)"
root="$(cd "$here/../.." && pwd)"
uascma="${1:-$root/build/uascma}"
out="${2:-$(mktemp -d)}"
mkdir -p "$out"
out="$(cd "$out" && pwd)"
# From the repository's root, so that the models record their data as data/bench/… (as the committed copies do).
cd "$root"
data="data/bench"

"$uascma" identify battery "$data/battery-nasa/B0005.csv" --cycle 1 --out "$out/cell.json" \
  --plot "$out/cell-fit.png"
"$uascma" validate battery --model "$out/cell.json" "$data/battery-nasa/B0005.csv" --cycle 2 \
  --window-low-v 3.0 --window-high-v 4.1 --plot "$out/cell-validation.png"

# The files' speed column is already the shaft speed (docs/modelling-choices.md#rcbenchmark-speed-column).
"$uascma" identify propulsion "$data/dyno-strawson/g8_7.csv" "$data/dyno-strawson/g8_11.csv" \
  --pole-pairs 1 --diameter-in 5 --out "$out/prop.json" --plot "$out/prop-fit.png"
"$uascma" identify propulsion "$data/dyno-strawson/g8_7.csv" --pole-pairs 1 --diameter-in 5 --out "$out/prop-2s.json"
"$uascma" validate propulsion --model "$out/prop-2s.json" "$data/dyno-strawson/g8_11.csv" --pole-pairs 1 \
  --plot "$out/prop-validation.png"
# The vehicle, its scenario and its campaign beside the models just identified (they name cell.json and prop.json
# relative to themselves). The copies committed in this folder are these files; cmp says so.
cp "$here/vehicle.yaml" "$here/scenario.yaml" "$here/campaign.yaml" "$out/"
cmp "$out/cell.json" "$here/cell.json" && cmp "$out/prop.json" "$here/prop.json"
"$uascma" simulate "$out/scenario.yaml"
"$uascma" campaign "$out/campaign.yaml" --db "$out/identified.db"
echo "models, vehicle and campaign in $out"
