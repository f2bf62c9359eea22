#!/usr/bin/env bash
# Installs the Debian 12 packages pushpred needs, and nothing when they are already there.
# Run as root (or through sudo). A second run only asks dpkg and returns.
set -euo pipefail
packages=(
  cmake g++ make pkg-config
  libsundials-dev libceres-dev libeigen3-dev libboost-test-dev libhdf5-dev
  nlohmann-json3-dev libcli11-dev libbenchmark-dev gnuplot-nox
  pybind11-dev python3-dev python3-numpy python3-pytest python3-matplotlib
  python3-pip python3-setuptools python3-wheel python3-venv
  clang-14 libclang-rt-14-dev jq
  libopenmpi-dev openmpi-bin
)
missing=()
for p in "${packages[@]}"; do
  dpkg-query -W -f='${Status}' "$p" 2>/dev/null | grep -q "install ok installed" || missing+=("$p")
done
if ((${#missing[@]} == 0)); then
  exit 0
fi
echo "install-deps: installing ${missing[*]}"
SUDO=""
if [ "$(id -u)" -ne 0 ]; then SUDO="sudo"; fi
$SUDO apt-get update -qq
DEBIAN_FRONTEND=noninteractive $SUDO apt-get install -y -qq --no-install-recommends "${missing[@]}"
