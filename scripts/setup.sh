#!/usr/bin/env bash
# Installs the Debian packages pilelab needs (only those missing; apt-get update first) and
# builds it with Ninja into build/. Safe to run again: it installs nothing twice and rebuilds
# only what changed (ccache keeps object files across clean builds).
set -euo pipefail
cd "$(dirname "$0")/.."

packages=(
  build-essential cmake ninja-build ccache pkg-config
  libeigen3-dev libtomlplusplus-dev nlohmann-json3-dev libcli11-dev libspdlog-dev
  libhdf5-openmpi-dev libopenmpi-dev openmpi-bin
  libcgal-dev libgmp-dev libmpfr-dev
  libgtest-dev libgmock-dev libbenchmark-dev
  gmsh libgmsh-dev libdeal.ii-dev
  python3 python3-numpy python3-matplotlib python3-h5py python3-meshio
  # Optional for python/pilelab (Run.profiles_frame); docs/PYTHON.md's tour, tested, uses it.
  python3-pandas
  # For the ParaView test (tests/scripts/paraview_pictures_test.sh): pvpython renders only
  # through an X display, so a virtual one.
  python3-paraview xvfb
)
missing=()
for p in "${packages[@]}"; do
  dpkg-query -W -f='${Status}' "$p" 2>/dev/null | grep -q "install ok installed" || missing+=("$p")
done
if ((${#missing[@]})); then
  echo "setup: installing ${missing[*]}"
  sudo=""
  [[ $(id -u) -ne 0 ]] && sudo="sudo"
  $sudo apt-get update
  DEBIAN_FRONTEND=noninteractive $sudo apt-get install -y --no-install-recommends "${missing[@]}"
fi

cmake -S . -B build -G Ninja -DCMAKE_BUILD_TYPE=Release
cmake --build build -j2
