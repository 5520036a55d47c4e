#!/usr/bin/env bash
# Sets everything up and runs the main jobs: pour 1.5 t of dry sand on the
# thesis's 8 m x 8 m yard (runs/pour-demo); the loader filling its bucket
# from a sand bank and loading a truck bed (runs/dig-demo); the default
# exercise, pile-to-zone, with its scripted operator as a second process
# over LCM, in lockstep, its frames recorded and its review page built
# (runs/session-demo); then validate the shipped loader and print its
# figures.
set -euo pipefail
cd "$(dirname "$0")/.."
scripts/setup.sh
./build/skidsim pour --out "${1:-runs/pour-demo}"
./build/skidsim dig --out "${2:-runs/dig-demo}"
# The session's own LCM channels (SKIDSIM_STATE@demo-PID...): another
# session on this host never crosses it.
session="demo-$$"
./build/skidsim operator scenarios/pile_to_zone.operator.xml --session "$session" --idle-s 5 &
operator=$!
./build/skidsim run scenarios/pile_to_zone.xml --mode lockstep --session "$session" --record --frame-width 640 \
  --frame-height 360 --out "${3:-runs/session-demo}"
wait "$operator" || true  # it stops when the session does
./build/skidsim review "${3:-runs/session-demo}"
./build/skidsim check
