#!/usr/bin/env bash
# Sets everything up and runs the main jobs: pour 1.5 t of dry sand on the
# thesis's 8 m x 8 m yard (runs/pour-demo); the loader filling its bucket
# from a sand bank and loading a truck bed (runs/dig-demo); then validate
# the shipped loader and print its figures.
set -euo pipefail
cd "$(dirname "$0")/.."
scripts/setup.sh
./build/skidsim pour --out "${1:-runs/pour-demo}"
./build/skidsim dig --out "${2:-runs/dig-demo}"
./build/skidsim check
