#!/usr/bin/env bash
# Installs the Debian packages uascma builds on (see shared/spec/dependencies.md).
# Runs as root (no sudo). Installs only what is missing, so a second run is quick.
set -euo pipefail

packages=(
  build-essential cmake pkg-config
  libeigen3-dev libyaml-cpp-dev nlohmann-json3-dev libcli11-dev libfmt-dev
  libgtest-dev libgmock-dev libbenchmark-dev
  libsqlite3-dev libtbb-dev
  libopenmpi-dev openmpi-bin
  libompl-dev libboost-serialization-dev libboost-filesystem-dev libboost-system-dev
  libboost-math-dev
  libosmium2-dev libprotozero-dev libexpat1-dev libbz2-dev zlib1g-dev libproj-dev
  python3-matplotlib python3-numpy
  clang libclang-rt-14-dev
  pybind11-dev python3-dev python3-pandas python3-pytest
)

missing=()
for p in "${packages[@]}"; do
  if ! dpkg-query -W -f='${Status}' "$p" 2>/dev/null | grep -q "install ok installed"; then
    missing+=("$p")
  fi
done

if ((${#missing[@]} == 0)); then
  echo "deps: all ${#packages[@]} packages present"
  exit 0
fi

if [[ $(id -u) -ne 0 ]]; then
  echo "deps: missing packages (${missing[*]}); run this script as root" >&2
  exit 1
fi

echo "deps: installing ${#missing[@]} packages: ${missing[*]}"
export DEBIAN_FRONTEND=noninteractive
apt-get update -qq
apt-get install -y -qq --no-install-recommends "${missing[@]}" >/dev/null
echo "deps: done"
