#!/usr/bin/env bash
# Sets everything up and runs the whole test suite: the parsers' libFuzzer
# harnesses for a bounded time (SKIDSIM_FUZZ_SECONDS each, default 20;
# scripts/fuzz.sh builds them in build-fuzz/ with ASan and UBSan), then CTest
# (GoogleTest) on build/.
set -euo pipefail
cd "$(dirname "$0")/.."
scripts/setup.sh
bash scripts/fuzz.sh "${SKIDSIM_FUZZ_SECONDS:-20}"
ctest --test-dir build --output-on-failure -j"$(nproc)"
