#!/usr/bin/env bash
# How low can one flight's 200 Hz step go? (Our target: <= 2,500 instructions per step.) Counts the instructions per
# step (bench/step_instructions.sh: callgrind, Simulator::Run only) of examples/nominal.yaml under
#  1. the subsystem rates that may run slower than the GNC loop, every pair of the pack's rate (options.pack_rate_hz;
#     10 Hz is the default, README "Subsystem rates") and the Dryden filter's (options.wind_rate_hz; 200 Hz is the
#     default): the best choice in hindsight, whatever it does to the results;
#  2. parts of the step removed altogether (not a configuration anyone should fly: a bound on what the rest costs):
#     the IMM (options.fault_detection: false), the turbulence (wind.turbulence: none), the drag feed-forward.
# One flight's count does not depend on the machine's load. ~40 callgrind runs of ~2 s each.
#   bash bench/step_floor.sh [BUILD_DIR]
set -euo pipefail
build="$(cd "${1:-build}" && pwd)"
here="$(cd "$(dirname "$0")/.." && pwd)"
if ! command -v valgrind > /dev/null; then
  echo "step floor: skipped (valgrind is not installed: bash scripts/install-deps.sh test-tools)"
  exit 0
fi
work="$(mktemp -d)"
trap 'rm -rf "$work"' EXIT

# variant NAME TURBULENCE OPTION...: nominal.yaml with its turbulence category and an options block.
variant() {
  local name=$1 turbulence=$2
  shift 2
  sed "s/turbulence: low-light/turbulence: $turbulence/" "$here/examples/nominal.yaml" > "$work/$name.yaml"
  grep -q "turbulence: $turbulence" "$work/$name.yaml" || {
    echo "step floor: examples/nominal.yaml no longer has 'turbulence: low-light'" >&2
    exit 1
  }
  if (($# > 0)); then
    echo "options:" >> "$work/$name.yaml"
    for option in "$@"; do echo "  $option" >> "$work/$name.yaml"; done
  fi
}
instructions() {  # instructions NAME: the instructions per step of variant NAME
  bash "$here/bench/step_instructions.sh" "$build" "$work/$1.yaml" | sed -E 's/^instructions per 200 Hz step: ([0-9]+).*/\1/'
}
count() {  # count NAME LABEL: a line of LABEL and variant NAME's instructions per step
  printf '%-64s %6s\n' "$2" "$(instructions "$1")"
}

echo "1. pack rate x Dryden rate (Hz): instructions per 200 Hz step of examples/nominal.yaml"
printf '%-10s' "pack\\wind"
winds=(200 50 20 10 5)
for wind in "${winds[@]}"; do printf '%8s' "$wind"; done
echo
for pack in 200 100 50 20 10 5 2 1; do
  printf '%-10s' "$pack"
  for wind in "${winds[@]}"; do
    variant "p${pack}w${wind}" low-light "pack_rate_hz: $pack" "wind_rate_hz: $wind"
    printf '%8s' "$(instructions "p${pack}w${wind}")"
  done
  echo
done
echo
echo "2. parts removed (the pack at its default 10 Hz unless named)"
variant as-is low-light
count as-is "examples/nominal.yaml as it is"
variant no-imm low-light "fault_detection: false"
count no-imm "without the IMM"
variant no-turbulence none
count no-turbulence "without turbulence"
variant core none "fault_detection: false"
count core "without the IMM and turbulence"
variant core-pack1 none "fault_detection: false" "pack_rate_hz: 1"
count core-pack1 "without the IMM and turbulence, the pack at 1 Hz"
variant bare none "fault_detection: false" "pack_rate_hz: 1" "drag_feedforward: false"
count bare "... and without the drag feed-forward"
