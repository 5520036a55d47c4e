#!/usr/bin/env bash
# Installs the Debian packages skidsim needs (idempotent; as root, or through
# sudo), then configures and builds it (CMake, Release) in ./build.
set -euo pipefail
cd "$(dirname "$0")/.."

PACKAGES=(
  build-essential cmake pkg-config
  libeigen3-dev          # terrain, geometry
  libpng-dev             # height maps, images
  libtinyxml2-dev        # soil table, exercises
  nlohmann-json3-dev     # metadata, summaries, reports
  libcli11-dev           # the skidsim command line
  libgtest-dev libgmock-dev  # tests
  libbenchmark-dev       # skidsim bench
  libbullet-dev          # the loader's multibody (double build: bullet-float64)
  liburdfdom-dev         # the loader's URDF
  libassimp-dev          # visual meshes
  liblcm-dev liblcm-bin libglib2.0-dev  # LCM: messages, lcm-gen, lcm-logger (pkg-config lcm needs glib)
)

missing=()
for p in "${PACKAGES[@]}"; do
  dpkg-query -W -f='${Status}' "$p" 2>/dev/null | grep -q "install ok installed" || missing+=("$p")
done
if ((${#missing[@]})); then
  SUDO=()
  if [[ $(id -u) -ne 0 ]]; then SUDO=(sudo); fi
  echo "setup: installing ${missing[*]}"
  "${SUDO[@]}" apt-get update -qq
  DEBIAN_FRONTEND=noninteractive "${SUDO[@]}" apt-get install -y -qq --no-install-recommends "${missing[@]}"
fi

cmake -S . -B build -DCMAKE_BUILD_TYPE="${SKIDSIM_BUILD_TYPE:-Release}" >/dev/null
cmake --build build -j"$(nproc)"
