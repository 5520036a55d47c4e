#!/usr/bin/env bash
# Installs the Debian packages skidsim needs (idempotent; as root, or through
# sudo), then configures and builds it (CMake, Release) in ./build.
set -euo pipefail
cd "$(dirname "$0")/.."

source scripts/packages.sh
install_packages setup "${SKIDSIM_PACKAGES[@]}"

cmake -S . -B build -DCMAKE_BUILD_TYPE="${SKIDSIM_BUILD_TYPE:-Release}" >/dev/null
cmake --build build -j"$(nproc)"
