#!/usr/bin/env bash
# Installs the Debian 12 packages snag needs to build, test and benchmark.
# Idempotent: safe to run again; apt-get skips what is already installed.
set -euo pipefail

packages=(
  build-essential cmake ninja-build pkg-config git
  libtbb-dev libcli11-dev nlohmann-json3-dev libeigen3-dev libsimdjson-dev libyaml-cpp-dev
  libassimp-dev
  libcgal-dev libgmp-dev libmpfr-dev
  libopenvdb-dev libboost-iostreams-dev
  libgtest-dev libgmock-dev libbenchmark-dev
  clang libclang-rt-14-dev
  mandoc man-db python3
  chromium libjs-chart.js libjs-three
  libopenmpi-dev openmpi-bin
)

sudo=""
if [ "$(id -u)" -ne 0 ]; then
  command -v sudo >/dev/null || { echo "setup.sh: run as root or install sudo" >&2; exit 1; }
  sudo="sudo"
fi

export DEBIAN_FRONTEND=noninteractive
$sudo apt-get update -qq
$sudo apt-get install -y -qq --no-install-recommends "${packages[@]}" >/dev/null
echo "setup.sh: packages installed"
