#!/usr/bin/env bash
# Prints the final-state hash of every shipped exercise played by its own
# operator script (fast mode), in the format of tests/data/final_state_hashes.txt,
# so a refactoring can be shown to change no session: diff the two.
#   scripts/state_hashes.sh [BUILD_DIR]      (default: build)
set -euo pipefail
cd "$(dirname "$0")/.."
bin=${1:-build}/skidsim
work=$(mktemp -d)
trap 'rm -rf "$work"' EXIT
for exercise in scenarios/*.xml; do
  name=$(basename "$exercise" .xml)
  [[ $name == *.operator* ]] && continue
  script=scenarios/$name.operator.xml
  [[ -f $script ]] || continue
  "$bin" run "$exercise" --script "$script" --out "$work/$name" >/dev/null
  hash=$(grep -o '"final_state_hash": *"[0-9a-f]*"' "$work/$name/report.json" | grep -o '[0-9a-f]\{16\}')
  echo "$name $hash"
done
