#!/usr/bin/env bash
# Installs the Debian packages uascma builds on, by group:
#   build       the compilers and the libraries of the library and the command-line tool   (make demo)
#   plots       Python's matplotlib, which draws every figure (uascma plot, --plot)        (make demo)
#   test        what the tests, benchmarks and the Python module compile against, and MPI  (make test)
#   test-tools  what the tests run: valgrind, pytest and pandas, Chromium, Node.js          (make test)
#   fuzz        clang and its sanitizer runtimes                        (make fuzz, make check-sanitizers)
# Usage: install-deps.sh [GROUP...]   (default: build plots test test-tools). Runs as root (no sudo). Installs only
# what is missing, so a second run is quick.
#        install-deps.sh --start DIR GROUP...   the same in the background (output in DIR/install.log)
#        install-deps.sh --wait DIR             waits for it; fails, with its log, if it failed
# The Makefile compiles while the packages only the finished build needs (plots, test-tools) install: on this
# project's 2-core machine dpkg spent most of its time waiting for the disk (docs/performance.md#set-up-time).
set -euo pipefail

build=(
  build-essential cmake ninja-build pkg-config
  libeigen3-dev libyaml-cpp-dev nlohmann-json3-dev libcli11-dev libfmt-dev
  libsqlite3-dev
  libboost-math-dev
  libosmium2-dev libprotozero-dev libexpat1-dev libbz2-dev zlib1g-dev libproj-dev
  python3  # generates the MAVLink codec from its message definitions (src/mavlink/CMakeLists.txt)
)
plots=(
  python3-matplotlib python3-numpy
)
test=(
  libopenmpi-dev openmpi-bin  # campaigns across MPI ranks (uascma-mpi); the demo builds without them
  libgtest-dev libbenchmark-dev
  pybind11-dev python3-dev
)
test_tools=(
  valgrind  # callgrind: the instructions per GNC step of `make bench` (bench/step_instructions.sh)
  python3-pandas python3-pytest
  chromium  # the browser test of `uascma reproduce`'s page (tests/apps/reproduce_browser_test.py)
  nodejs npm  # the MAVLink interoperability test against node-mavlink (tests/mavlink/node/); see below
)
fuzz=(
  clang libclang-rt-14-dev
)

# --start DIR GROUP...: this script again in the background; --wait DIR: its end and status.
if [[ ${1:-} == --start ]]; then
  dir=$2
  shift 2
  mkdir -p "$dir"
  rm -f "$dir/status"
  # The status is written whether the install succeeds or fails (set -e would end the subshell before it).
  ( if bash "$0" "$@" >"$dir/install.log" 2>&1; then echo 0; else echo $?; fi >"$dir/status" ) </dev/null &
  echo "deps: installing ${*} in the background (log: $dir/install.log)"
  exit 0
fi
if [[ ${1:-} == --wait ]]; then
  dir=$2
  [[ -d $dir ]] || exit 0  # nothing was started
  until [[ -s $dir/status ]]; do sleep 1; done
  status=$(cat "$dir/status")
  cat "$dir/install.log"
  rm -rf "$dir"
  exit "$status"
fi

groups=("$@")
((${#groups[@]} > 0)) || groups=(build plots test test-tools)
packages=()
for group in "${groups[@]}"; do
  case "$group" in
    build) packages+=("${build[@]}") ;;
    plots) packages+=("${plots[@]}") ;;
    test) packages+=("${test[@]}") ;;
    test-tools) packages+=("${test_tools[@]}") ;;
    fuzz) packages+=("${fuzz[@]}") ;;
    *) echo "deps: unknown group '$group' (expected build, plots, test, test-tools or fuzz)" >&2; exit 2 ;;
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
# The lock timeout lets an install wait for one still running in the background (--start) instead of failing.
apt_options=(-o DPkg::Lock::Timeout=1800)
# dpkg syncs each file it unpacks to the disk; on this project's machine that was over half of apt's time (the build
# group: 148 s with it, 66 s without). --force-unsafe-io leaves the syncing to the kernel: a power cut during the
# install may leave a package to reinstall. UASCMA_DEPS_SAFE_IO=1 keeps dpkg's default.
[[ ${UASCMA_DEPS_SAFE_IO:-0} == 1 ]] || apt_options+=(-o Dpkg::Options::=--force-unsafe-io)
# Package lists refreshed within the hour (an earlier group of the same `make`) are not fetched again.
if [[ -z $(find /var/lib/apt/lists -maxdepth 1 -name '*_Packages*' -mmin -60 -print -quit 2>/dev/null) ]]; then
  apt-get "${apt_options[@]}" update -qq
fi
apt-get "${apt_options[@]}" install -y -qq --no-install-recommends "${missing[@]}" >/dev/null
echo "deps: done"
