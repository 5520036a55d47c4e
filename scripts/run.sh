#!/usr/bin/env bash
# Sets everything up and runs the main job: pour 1.5 t of dry sand on the
# thesis's 8 m x 8 m yard and write the run directory runs/pour-demo; then
# validate the shipped loader and print its figures.
set -euo pipefail
cd "$(dirname "$0")/.."
scripts/setup.sh
./build/skidsim pour --out "${1:-runs/pour-demo}"
./build/skidsim check
