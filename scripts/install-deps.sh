#!/usr/bin/env bash
# Installs the Debian packages uascma builds on, by group:
#   build  the library, the command-line tool and the demo's plots  (make demo)
#   test   MPI, the tests, benchmarks and the Python module         (make test: build + test)
#   fuzz   clang and its sanitizer runtimes                         (make fuzz, make check-sanitizers)
# Usage: install-deps.sh [GROUP...]   (default: build test). Runs as root (no sudo). Installs only what is
# missing, so a second run is quick.
set -euo pipefail

build=(
  build-essential cmake ninja-build pkg-config
  libeigen3-dev libyaml-cpp-dev nlohmann-json3-dev libcli11-dev libfmt-dev
  libsqlite3-dev
  libboost-math-dev
  libosmium2-dev libprotozero-dev libexpat1-dev libbz2-dev zlib1g-dev libproj-dev
  python3-matplotlib python3-numpy
)
test=(
  libopenmpi-dev openmpi-bin  # campaigns across MPI ranks (uascma-mpi); the demo builds without them
  libgtest-dev libbenchmark-dev
  valgrind  # callgrind: the instructions per GNC step of `make bench` (bench/step_instructions.sh)
  pybind11-dev python3-dev python3-pandas python3-pytest
  chromium  # the browser test of `uascma reproduce`'s page (tests/apps/reproduce_browser_test.py)
  nodejs npm  # the MAVLink interoperability test against node-mavlink (tests/mavlink/node/); see below
)
fuzz=(
  clang libclang-rt-14-dev
)

groups=("$@")
((${#groups[@]} > 0)) || groups=(build test)
packages=()
for group in "${groups[@]}"; do
  case "$group" in
    build) packages+=("${build[@]}") ;;
    test) packages+=("${test[@]}") ;;
    fuzz) packages+=("${fuzz[@]}") ;;
    *) echo "deps: unknown group '$group' (expected build, test or fuzz)" >&2; exit 2 ;;
  esac
done

missing=()
for p in "${packages[@]}"; do
  # Node.js from another source (e.g. NodeSource's nodejs package, which carries its own npm and conflicts with
  # Debian's npm) serves the test as well: Debian's packages are installed only when the commands are missing.
  if [[ $p == nodejs || $p == npm ]] && command -v node >/dev/null && command -v npm >/dev/null; then
    continue
  fi
  if ! dpkg-query -W -f='${Status}' "$p" 2>/dev/null | grep -q "install ok installed"; then
    missing+=("$p")
  fi
done

if ((${#missing[@]} == 0)); then
  echo "deps: all ${#packages[@]} packages present (${groups[*]})"
  exit 0
fi

if [[ $(id -u) -ne 0 ]]; then
  echo "deps: missing packages (${missing[*]}); run this script as root" >&2
  exit 1
fi

echo "deps: installing ${#missing[@]} packages (${groups[*]}): ${missing[*]}"
export DEBIAN_FRONTEND=noninteractive
apt-get update -qq
apt-get install -y -qq --no-install-recommends "${missing[@]}" >/dev/null
echo "deps: done"
