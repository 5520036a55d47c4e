#!/usr/bin/env bash
# DEM reference for the earthmoving equation, for wheels on soft soil and for fast granular
# flows: installs LIGGGHTS if missing, regenerates the meshes, runs every deck of dem/ in order
# (calibration, bed, blade runs, bucket; the wheel bed, its sinkage plates and the wheel runs;
# the collapsing columns) and post-processes them into the committed CSVs. See dem/README.md.
#
#   scripts/dem_reference.sh [stage ...]     stages: meshes pile shear slide chute erodible fed_heap
#                                            stopping impact bed blade bucket wheel_bed plate wheel
#                                            chute_post erodible_post fed_heap_post stopping_post
#                                            impact_post post wheel_post collapse collapse_post friction
#                                            friction_post (default: all, in that order);
#                                            optional stage "wide": the deep vertical cut in a
#                                            0.5 m wide bin (its own bed, about 25 min more),
#                                            then "post"
#   DEM_JOBS=2 scripts/dem_reference.sh      run independent decks two at a time (default 1)
#   DEM_SCRATCH=DIR                          dumps, restarts, logs (default <repo>/scratch/dem, git-ignored)
#   DEM_FRICTION_MU_RS="0.15"                the friction side study's materials (default "0.6 0.15")
#
# Takes about seven and two thirds hours on one core (see dem/results_meta.csv). Never run in CI.
set -euo pipefail

ROOT=$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)
DEM="$ROOT/dem"
SCRATCH=${DEM_SCRATCH:-$ROOT/scratch/dem}
JOBS=${DEM_JOBS:-1}
MESHES="$SCRATCH/meshes"
TIMES="$SCRATCH/times"

# shellcheck source=scripts/packages.sh
source "$ROOT/scripts/packages.sh"
install_packages dem_reference liggghts
LIGGGHTS=${LIGGGHTS:-$(command -v liggghts)}
PY=${PYTHON:-python3}

mkdir -p "$SCRATCH" "$TIMES"
rm -f "$SCRATCH"/failed.*
mkdir -p "$SCRATCH/pile" "$SCRATCH/shear" "$SCRATCH/slide" "$SCRATCH/slide_rim" "$SCRATCH/blade" "$SCRATCH/bucket" \
  "$SCRATCH/wheel"

# The DEM wheel's load (N): chosen from the plate tests' Bekker parameters so that the
# Wong-Reece closed form sinks the towed wheel 0.07 of its diameter and its largest pressure
# stays inside the plates' calibrated range (dem/README.md).
WHEEL_LOAD_N=${WHEEL_LOAD_N:-150}
# The wheel runs: towed (free to spin) and driven or braked at these slips.
WHEEL_SLIPS=(0.10 0.20 0.40 0.60 -0.30)

# rel PATH DIR: PATH relative to DIR. LIGGGHTS 3.8.0 (Debian) was seen to abort at random,
# without a message, while importing a servo mesh when the command line held long absolute
# paths; every file name is handed to the decks relative to the deck's folder.
rel() { realpath -m --relative-to="$2" "$1"; }

# run_deck NAME DIR DECK [liggghts args...]: runs one deck in DIR (decks use paths relative to
# their folder), niced, serial; its log goes to $SCRATCH/NAME.log and its wall time to $TIMES/NAME.
run_deck() {
  local name=$1 dir=$2 deck=$3
  shift 3
  local t0 t1
  echo "dem_reference: $name"
  t0=$(date +%s%N)
  if ! (cd "$dir" && nice -n 10 "$LIGGGHTS" -in "$deck" -log "$(rel "$SCRATCH/$name.log" "$dir")" -echo none "$@" \
      > "$SCRATCH/$name.out" 2>&1); then
    echo "dem_reference: $name failed, see $SCRATCH/$name.log" >&2
    touch "$SCRATCH/failed.$name"
    return 1
  fi
  t1=$(date +%s%N)
  printf '%s,%d.%d\n' "$name" $(((t1 - t0) / 1000000000)) $((((t1 - t0) / 100000000) % 10)) > "$TIMES/$name"
}

# wait_ok: waits for every deck in flight; stops if one failed
wait_ok() {
  wait
  if compgen -G "$SCRATCH/failed.*" > /dev/null; then
    echo "dem_reference: failed decks: $(cd "$SCRATCH" && ls failed.* | sed 's/failed.//' | xargs)" >&2
    exit 1
  fi
}

# throttle: at most $JOBS decks in flight
throttle() { while (($(jobs -rp | wc -l) >= JOBS)); do wait -n || true; done; }

stage_meshes() { "$PY" "$DEM/tools/meshes.py" "$MESHES"; }

stage_pile() {
  local c="$DEM/calibration"
  throttle; run_deck pile "$c" pile.in -var meshdir "$(rel "$MESHES" "$c")" -var out "$(rel "$SCRATCH/pile" "$c")" &
}

stage_shear() {
  local sn c="$DEM/calibration"
  for sn in 2000 5000 10000; do
    throttle
    run_deck "shear_$sn" "$c" shear_box.in -var sn "$sn" -var meshdir "$(rel "$MESHES" "$c")" \
      -var out "$(rel "$SCRATCH/shear/shear_$sn.txt" "$c")" &
  done
}

stage_slide() {
  local sn c="$DEM/calibration"
  for sn in 2000 5000; do
    throttle
    run_deck "slide_$sn" "$c" sliding_plate.in -var sn "$sn" -var meshdir "$(rel "$MESHES" "$c")" \
      -var out "$(rel "$SCRATCH/slide/slide_$sn.txt" "$c")" &
  done
  # the wheel rim's material (type 3) on the soil, at the wheel's stresses
  for sn in 10000 20000; do
    throttle
    run_deck "slide_rim_$sn" "$c" sliding_plate.in -var sn "$sn" -var ptype 3 -var meshdir "$(rel "$MESHES" "$c")" \
      -var out "$(rel "$SCRATCH/slide_rim/slide_rim_$sn.txt" "$c")" &
  done
}

# Inclined layers (dem/calibration/chute.in): a flowing layer's friction as it slows to rest, on
# the grains themselves (five thicknesses: thin layers stop on steeper slopes, and the thick
# flow's limit), on the collapsing
# columns' floor (three) and between the slot's steel side walls (two, on that floor). Each run:
# "NAME BASE LAYERS WALL_GAP_M KICK_DEG ANGLES...".
CHUTE_RUNS=(
  "grains_n4 1 4 0 50 44 42 40 38 36 34 32 30"
  "grains_n8 1 8 0 42 34 32 30 28 26 24 22"
  "grains_n16 1 16 0 38 32 30 28 26 24 22 20 18"
  "grains_n32 1 32 0 38 32 30 28 26 24 22 20 18"
  "grains_n64 1 64 0 38 26 24 22 20 18"
  "floor_n4 3 4 0 38 24 20 16 12"
  "floor_n8 3 8 0 38 24 22 20 18 16 14 12"
  "floor_n16 3 16 0 38 32 30 28 26 24 22 20 18 16 14 12 10"
  "walls_n4 3 4 0.08 42 36 34 32 30 28 26 24 22 20"
  "walls_n8 3 8 0.08 46 42 40 38 36 34 32 30 28 26"
)
stage_chute() {
  local run name base layers gap kick c="$DEM/calibration"
  mkdir -p "$SCRATCH/chute"
  for run in "${CHUTE_RUNS[@]}"; do
    read -r name base layers gap kick angles <<< "$run"
    throttle
    # shellcheck disable=SC2086  # the angles are one argument each
    run_deck "chute_$name" "$c" chute.in -var base "$base" -var layers "$layers" -var W "$gap" -var kick "$kick" \
      -var theta $angles -var out "$(rel "$SCRATCH/chute" "$c")" &
  done
}

# The inclined layers' stop angles, then the calibrated material (material.csv) with them.
stage_chute_post() {
  wait_ok
  local cal="$DEM/calibration/results"
  "$PY" "$DEM/tools/chute.py" "$cal" "$SCRATCH/chute"
  "$PY" "$DEM/tools/rate_friction.py" "$cal"
  "$PY" "$DEM/tools/material_csv.py" "$cal" "$DEM/calibration/material.csv"
  write_meta
}

# A layer set moving on a deep bed of its own grains at rest (dem/calibration/erodible.in):
# which thickness the thin-layer law reads (the flowing layer's, or the grains' whole depth),
# and whether the bed, steeper than the thick layer's stop angle, is carried away under it.
# 4 grains at 0.5 m/s at 26, 28, 29 and 30 deg (at 29 and 30 deg the bed, 24 grains deep, flows
# by itself: its start angle, and the control); 8 grains at 1 m/s at 26 and 28 deg and 12 grains
# at 1.5 m/s at 26 deg, 4 s on.
ERODIBLE_RUNS=("4 0.5 26 2.0" "4 0.5 28 2.0" "4 0.5 29 2.0" "4 0.5 30 2.0" "8 1.0 26 4.0" "8 1.0 28 4.0"
  "12 1.5 26 4.0")
stage_erodible() {
  local run top v0 th trun c="$DEM/calibration"
  mkdir -p "$SCRATCH/erodible"
  for run in "${ERODIBLE_RUNS[@]}"; do
    read -r top v0 th trun <<< "$run"
    throttle
    run_deck "erodible_top${top}_theta$th" "$c" erodible.in -var top "$top" -var v0 "$v0" -var theta "$th" \
      -var trun "$trun" -var out "$(rel "$SCRATCH/erodible" "$c")" &
  done
}

stage_erodible_post() {
  wait_ok
  "$PY" "$DEM/tools/erodible.py" "$DEM/calibration/results" "$SCRATCH/erodible"
  write_meta
}

# A heap fed at known rates (dem/calibration/fed_heap.in): the slope the slow regime's surface
# flow stands at for each flux Q (m^2/s of bulk soil per metre of width), 20 s each, measured
# from 6 s on (dem/tools/fed_heap.py): the automaton's flux law against the grains'.
FED_HEAP_Q_M2_S=(0.0005 0.001 0.002 0.004 0.008 0.016 0.032)
FED_HEAP_TEND_S=20
stage_fed_heap() {
  local q c="$DEM/calibration"
  mkdir -p "$SCRATCH/fed_heap"
  for q in "${FED_HEAP_Q_M2_S[@]}"; do
    throttle
    run_deck "fed_heap_Q$q" "$c" fed_heap.in -var Q "$q" -var tend "$FED_HEAP_TEND_S" \
      -var out "$(rel "$SCRATCH/fed_heap" "$c")" &
  done
}

stage_fed_heap_post() {
  wait_ok
  "$PY" "$DEM/tools/fed_heap.py" "$SCRATCH/fed_heap" "$DEM/calibration/results"
  write_meta
}

# A flowing layer coming to rest (dem/calibration/stopping.in): set flowing down 38 deg for 0.6 s,
# then on level ground (or 15 deg), its grains dumped through its depth every 5 ms as it stops
# (dem/tools/stopping.py): where it lays its base down and how far its mass travels, on its own
# grains (8, 16 and 32 grains thick) and on the columns' floor (8 and 16). Each run:
# "BASE LAYERS THETA_DEG".
STOPPING_RUNS=("1 8 0" "1 16 0" "1 32 0" "1 16 15" "3 8 0" "3 16 0")
stage_stopping() {
  local run base layers theta c="$DEM/calibration"
  mkdir -p "$SCRATCH/stopping"
  for run in "${STOPPING_RUNS[@]}"; do
    read -r base layers theta <<< "$run"
    throttle
    run_deck "stopping_base${base}_n${layers}_theta$theta" "$c" stopping.in -var base "$base" -var layers "$layers" \
      -var theta "$theta" -var out "$(rel "$SCRATCH/stopping" "$c")" &
  done
}

stage_stopping_post() {
  wait_ok
  "$PY" "$DEM/tools/stopping.py" "$SCRATCH/stopping" "$DEM/calibration/results"
  write_meta
}

# A dense granular jet on the floor: the columns' deck (dem/collapse/column.in) as a column 0.08 m
# across (10 grains) and 0.4 m long, let go 0.3 m above the floor, dumped every 4 ms; how much of
# its fall speed the sheet it sends out keeps, and its deposit (dem/tools/impact.py): a landing
# from a body, as a bucket's dump lands, beside the dropped block of the collapse stage.
IMPACT_ARGS=(-var a 10 -var r0 0.04 -var drop 0.3 -var dtout 0.004 -var tend 0.8)
stage_impact() {
  local c="$DEM/collapse"
  mkdir -p "$SCRATCH/impact"
  throttle
  run_deck impact_jet "$c" column.in "${IMPACT_ARGS[@]}" -var out "$(rel "$SCRATCH/impact" "$c")" &
}

stage_impact_post() {
  wait_ok
  "$PY" "$DEM/tools/impact.py" "$SCRATCH/impact" "$DEM/calibration/results"
  "$PY" "$DEM/tools/material_csv.py" "$DEM/calibration/results" "$DEM/calibration/material.csv"
  write_meta
}

stage_bed() {
  throttle; run_deck bed "$DEM/blade" bed.in -var scratch "$(rel "$SCRATCH" "$DEM/blade")" &
  wait_ok  # the blade runs and the bucket start from its restart
}

stage_blade() {
  local rake d b="$DEM/blade"
  for rake in 90 60; do
    for d in 40 70; do
      throttle
      run_deck "blade_a${rake}_d${d}mm" "$b" blade.in -var rake "$rake" \
        -var depth "$(printf '0.%03d' "$d")" -var scratch "$(rel "$SCRATCH" "$b")" \
        -var meshdir "$(rel "$MESHES" "$b")" -var out "$(rel "$SCRATCH/blade/blade_a${rake}_d${d}mm.txt" "$b")" \
        -var heap "$(rel "$SCRATCH/blade/heap_a${rake}_d${d}mm.dump" "$b")" &
    done
  done
}

stage_bucket() {
  local k="$DEM/bucket"
  throttle; run_deck bucket "$k" bucket.in -var scratch "$(rel "$SCRATCH" "$k")" -var meshdir "$(rel "$MESHES" "$k")" \
    -var out "$(rel "$SCRATCH/bucket" "$k")" &
}

stage_wide() {
  local b="$DEM/blade" w="$SCRATCH/wide"
  mkdir -p "$w"
  throttle; run_deck wide_bed "$b" bed.in -var Ly 0.50 -var scratch "$(rel "$w" "$b")" &
  wait_ok
  throttle
  run_deck wide_blade_a90_d70mm "$b" blade.in -var yh 0.25 -var rake 90 -var depth 0.070 \
    -var scratch "$(rel "$w" "$b")" -var meshdir "$(rel "$MESHES" "$b")" \
    -var out "$(rel "$w/blade_a90_d70mm.txt" "$b")" -var heap "$(rel "$w/heap_a90_d70mm.dump" "$b")" &
}

stage_wheel_bed() {
  throttle
  run_deck wheel_bed "$DEM/blade" bed.in -var Lx 0.70 -var scratch "$(rel "$SCRATCH/wheel" "$DEM/blade")" &
  wait_ok  # the plates and the wheel runs start from its restart
}

stage_plate() {
  local r w="$DEM/wheel"
  for r in 30 50; do
    throttle
    run_deck "plate_r$r" "$w" plate.in -var R "0.0$r" -var scratch "$(rel "$SCRATCH/wheel" "$w")" \
      -var meshdir "$(rel "$MESHES" "$w")" -var out "$(rel "$SCRATCH/wheel/plate_r$r.txt" "$w")" &
  done
}

stage_wheel() {
  local s w="$DEM/wheel"
  throttle
  run_deck wheel_towed "$w" wheel.in -var towed 1 -var W "$WHEEL_LOAD_N" -var scratch "$(rel "$SCRATCH/wheel" "$w")" \
    -var meshdir "$(rel "$MESHES" "$w")" -var out "$(rel "$SCRATCH/wheel/wheel_towed.csv" "$w")" &
  for s in "${WHEEL_SLIPS[@]}"; do
    throttle
    run_deck "wheel_s$s" "$w" wheel.in -var slip "$s" -var W "$WHEEL_LOAD_N" \
      -var scratch "$(rel "$SCRATCH/wheel" "$w")" -var meshdir "$(rel "$MESHES" "$w")" \
      -var out "$(rel "$SCRATCH/wheel/wheel_s$s.csv" "$w")" &
  done
}

# The wheel's soil and runs: Janosi's K from the shear box's curves, the rim's friction from
# its sliding plate, Bekker's and the unloading line's parameters from the plates, the wheel
# runs' steady means.
stage_wheel_post() {
  wait_ok
  local res="$DEM/wheel/results" cal="$DEM/calibration/results"
  mkdir -p "$res"
  "$PY" "$DEM/tools/janosi.py" "$cal/shear_curves.csv" "$cal/janosi.csv"
  "$PY" "$DEM/tools/slide.py" "$cal/sliding_plate_rim.csv" "$SCRATCH"/slide_rim/slide_rim_*.txt
  cp "$SCRATCH/wheel/bed.csv" "$res/bed.csv"
  "$PY" "$DEM/tools/plate_post.py" "$res" "$SCRATCH"/wheel/plate_r*.txt
  "$PY" "$DEM/tools/wheel_post.py" "$res" "$res/bekker.csv" "$cal/sliding_plate_rim.csv" "$SCRATCH"/wheel/wheel_*.csv
  write_meta
}

# Collapsing columns (issue "Fast granular flows"): axisymmetric columns of aspect ratio
# COLLAPSE_ASPECTS in a tube of radius 0.1 m, and one quasi-two-dimensional column (a slot 0.08 m
# wide) of aspect ratio COLLAPSE_SLOT_ASPECT.
COLLAPSE_ASPECTS=(0.5 1 2 4)
COLLAPSE_SLOT_ASPECT=2
# A load let go from a height: a column of aspect ratio 1 dropped COLLAPSE_DROP_M (4 r0) onto
# the floor, as a bucket's load (about 0.5 m across and high) is dumped from 2 m.
COLLAPSE_DROP_ASPECT=1
COLLAPSE_DROP_M=0.4
# The same grains in a tube twice as wide (r0 = 0.2 m, 25 grains per radius) at aspect ratios
# COLLAPSE_WIDE_ASPECTS, for COLLAPSE_WIDE_TEND_S of collapse: how the columns depend on r0 / d
# (the thin-layer law's grain scale) and how the deposit's toe beyond the edge scales
# (dem/collapse/results_r0_0.2; report/dem_columns.h, kWideTubeResults).
COLLAPSE_WIDE_R0_M=0.2
COLLAPSE_WIDE_TEND_S=1.4
COLLAPSE_WIDE_ASPECTS=(0.5 1 2)
stage_collapse() {
  local a c="$DEM/collapse"
  mkdir -p "$SCRATCH/collapse"
  for a in "${COLLAPSE_ASPECTS[@]}"; do
    throttle
    run_deck "collapse_tube_a$a" "$c" column.in -var a "$a" -var slot 0 -var out "$(rel "$SCRATCH/collapse" "$c")" &
  done
  throttle
  run_deck "collapse_slot_a$COLLAPSE_SLOT_ASPECT" "$c" column.in -var a "$COLLAPSE_SLOT_ASPECT" -var slot 1 \
    -var out "$(rel "$SCRATCH/collapse" "$c")" &
  throttle
  run_deck "collapse_drop_a$COLLAPSE_DROP_ASPECT" "$c" column.in -var a "$COLLAPSE_DROP_ASPECT" \
    -var drop "$COLLAPSE_DROP_M" -var out "$(rel "$SCRATCH/collapse" "$c")" &
  mkdir -p "$SCRATCH/collapse_wide"
  for a in "${COLLAPSE_WIDE_ASPECTS[@]}"; do
    throttle
    run_deck "collapse_wide_tube_a$a" "$c" column.in -var a "$a" -var slot 0 -var r0 "$COLLAPSE_WIDE_R0_M" -var tend "$COLLAPSE_WIDE_TEND_S" \
      -var out "$(rel "$SCRATCH/collapse_wide" "$c")" &
  done
}

# The collapses' fronts against time and final deposits.
stage_collapse_post() {
  wait_ok
  mkdir -p "$DEM/collapse/results"
  "$PY" "$DEM/tools/collapse.py" "$SCRATCH/collapse" "$DEM/collapse/results"
  "$PY" "$DEM/tools/collapse_profiles.py" "$SCRATCH/collapse" "$DEM/collapse/results"
  mkdir -p "$DEM/collapse/results_r0_$COLLAPSE_WIDE_R0_M"
  "$PY" "$DEM/tools/collapse.py" "$SCRATCH/collapse_wide" "$DEM/collapse/results_r0_$COLLAPSE_WIDE_R0_M"
  "$PY" "$DEM/tools/collapse_profiles.py" "$SCRATCH/collapse_wide" "$DEM/collapse/results_r0_$COLLAPSE_WIDE_R0_M"
  write_meta
}

# The friction side study (docs/fast_flows.md, "A rougher material, and a smoother one"): the same grains with their
# rolling friction each of FRICTION_MU_RS for 0.3 (dem/material.in, mu_r), each calibrated on the
# pile, the inclined layers (on the grains, four thicknesses; on the columns' floor) and the
# erodible bed alone, then its tubes of aspect ratio FRICTION_ASPECTS: whether the DEM's run-out
# follows the material's friction as the model's does. Results, with each calibration's own
# material.csv, in dem/collapse/results_mu_r<mu_r>. The layers are kicked above each material's
# repose and tilted to angles that bracket its stop angles; the bed's angles bracket its start.
read -r -a FRICTION_MU_RS <<< "${DEM_FRICTION_MU_RS:-0.6 0.15}"
FRICTION_ASPECTS=(0.5 1 2)
# And each material's tubes of FRICTION_WIDE_ASPECTS twice as wide (r0 = COLLAPSE_WIDE_R0_M, 25 grains
# per radius; results in results_mu_r<mu_r>/r0_<r0>): whether the DEM's response to the material
# holds with more grains per radius.
FRICTION_WIDE_ASPECTS=(1)
# friction_chute_runs MU_R: the inclined-layer runs, "NAME BASE LAYERS WALL_GAP_M KICK_DEG ANGLES..."
friction_chute_runs() {
  case $1 in
    0.6) printf '%s\n' "grains_n4 1 4 0 52 46 44 42 40 38 36 34 32 30" "grains_n8 1 8 0 48 40 38 36 34 32 30 28 26 24 22" \
      "grains_n16 1 16 0 46 36 34 32 30 28 26 24 22 20 18" "grains_n64 1 64 0 44 34 32 30 28 26 24 22 20" \
      "floor_n8 3 8 0 44 28 26 24 22 20 18 16 14 12" ;;
    *) printf '%s\n' "grains_n4 1 4 0 50 44 42 40 38 36 34 32 30 28" "grains_n8 1 8 0 42 34 32 30 28 26 24 22 20" \
      "grains_n16 1 16 0 38 32 30 28 26 24 22 20 18 16" "grains_n64 1 64 0 38 26 24 22 20 18 16" \
      "floor_n8 3 8 0 38 24 22 20 18 16 14 12 10" ;;
  esac
}
friction_erodible_angles() {
  case $1 in
    0.6) echo 29 30 31 32 33 ;;
    *) echo 23 24 25 26 27 28 29 ;;
  esac
}
stage_friction() {
  local mu run name base layers gap kick angles a th f c="$DEM/calibration" co="$DEM/collapse"
  for mu in "${FRICTION_MU_RS[@]}"; do
    f="$SCRATCH/friction_mu$mu"
    mkdir -p "$f/pile" "$f/chute" "$f/erodible" "$f/collapse" "$f/collapse_wide"
    throttle
    run_deck "friction_mu${mu}_pile" "$c" pile.in -var mu_r "$mu" -var meshdir "$(rel "$MESHES" "$c")" \
      -var out "$(rel "$f/pile" "$c")" &
    while read -r name base layers gap kick angles; do
      throttle
      # shellcheck disable=SC2086  # the angles are one argument each
      run_deck "friction_mu${mu}_chute_$name" "$c" chute.in -var mu_r "$mu" -var base "$base" -var layers "$layers" \
        -var W "$gap" -var kick "$kick" -var theta $angles -var out "$(rel "$f/chute" "$c")" &
    done < <(friction_chute_runs "$mu")
    for th in $(friction_erodible_angles "$mu"); do
      throttle
      run_deck "friction_mu${mu}_erodible_top4_theta$th" "$c" erodible.in -var mu_r "$mu" -var top 4 -var v0 0.5 \
        -var theta "$th" -var trun 2.0 -var out "$(rel "$f/erodible" "$c")" &
    done
    for a in "${FRICTION_ASPECTS[@]}"; do
      throttle
      run_deck "friction_mu${mu}_tube_a$a" "$co" column.in -var mu_r "$mu" -var a "$a" -var slot 0 \
        -var out "$(rel "$f/collapse" "$co")" &
    done
    for a in "${FRICTION_WIDE_ASPECTS[@]}"; do
      throttle
      run_deck "friction_mu${mu}_wide_tube_a$a" "$co" column.in -var mu_r "$mu" -var a "$a" -var slot 0 \
        -var r0 "$COLLAPSE_WIDE_R0_M" -var tend "$COLLAPSE_WIDE_TEND_S" -var out "$(rel "$f/collapse_wide" "$co")" &
    done
  done
}

stage_friction_post() {
  wait_ok
  local mu f res
  for mu in "${FRICTION_MU_RS[@]}"; do
    f="$SCRATCH/friction_mu$mu" res="$DEM/collapse/results_mu_r$mu"
    mkdir -p "$res"
    "$PY" "$DEM/tools/repose.py" "$f/pile/pile_final.dump" "$res/repose.csv"
    "$PY" "$DEM/tools/chute.py" "$res" "$f/chute"
    "$PY" "$DEM/tools/rate_friction.py" "$res"
    "$PY" "$DEM/tools/erodible.py" "$res" "$f/erodible"
    "$PY" "$DEM/tools/material_csv.py" --flow "$res" "$res/material.csv"
    "$PY" "$DEM/tools/collapse.py" "$f/collapse" "$res"
    "$PY" "$DEM/tools/collapse_profiles.py" "$f/collapse" "$res"
    mkdir -p "$res/r0_$COLLAPSE_WIDE_R0_M"
    "$PY" "$DEM/tools/collapse.py" "$f/collapse_wide" "$res/r0_$COLLAPSE_WIDE_R0_M"
    "$PY" "$DEM/tools/collapse_profiles.py" "$f/collapse_wide" "$res/r0_$COLLAPSE_WIDE_R0_M"
  done
  write_meta
}

stage_post() {
  wait_ok
  local cal="$DEM/calibration/results"
  mkdir -p "$cal" "$DEM/blade/results" "$DEM/bucket/results"
  "$PY" "$DEM/tools/repose.py" "$SCRATCH/pile/pile_final.dump" "$cal/repose.csv"
  "$PY" "$DEM/tools/shear.py" "$cal/shear_box.csv" "$cal/shear_curves.csv" "$SCRATCH"/shear/shear_*.txt
  "$PY" "$DEM/tools/slide.py" "$cal/sliding_plate.csv" "$SCRATCH"/slide/slide_*.txt
  cp "$SCRATCH/bed.csv" "$cal/bed.csv"
  "$PY" "$DEM/tools/material_csv.py" "$cal" "$DEM/calibration/material.csv"
  "$PY" "$DEM/tools/blade_post.py" "$DEM/blade/results" "$DEM/calibration/material.csv" "$SCRATCH/blade"
  "$PY" "$DEM/tools/heap.py" "$DEM/blade/results" "$DEM/calibration/material.csv" "$SCRATCH/blade"
  "$PY" "$DEM/tools/bucket_post.py" "$SCRATCH/bucket" "$DEM/bucket/results" "$DEM/calibration/material.csv"
  if [[ -f "$SCRATCH/wide/blade_a90_d70mm.txt" ]]; then
    "$PY" "$DEM/tools/blade_post.py" "$DEM/blade/results/wide_bin" "$DEM/calibration/material.csv" "$SCRATCH/wide"
  fi
  write_meta
}

# dem/results_meta.csv: the LIGGGHTS version and the wall time of each deck; decks not run this
# time keep their rows.
write_meta() {
  local version meta="$DEM/results_meta.csv" f deck rest
  version=$(dpkg-query -W -f='${Version}' liggghts 2>/dev/null || echo unknown)
  {
    echo "deck,wall_s,liggghts_version,date"
    {
      for f in "$TIMES"/*; do
        [[ -f $f ]] && echo "$(cat "$f"),$version,$(date -u -r "$f" +%Y-%m-%dT%H:%M:%SZ)"
      done
      if [[ -f $meta ]]; then
        tail -n +2 "$meta" | while IFS=, read -r deck rest; do
          [[ -f "$TIMES/$deck" ]] || echo "$deck,$rest"
        done
      fi
    } | sort
  } > "$meta.tmp"
  mv "$meta.tmp" "$meta"
}

stages=("$@")
((${#stages[@]})) || stages=(meshes pile shear slide chute erodible fed_heap stopping impact bed blade bucket wheel_bed plate
  wheel chute_post erodible_post fed_heap_post stopping_post impact_post post wheel_post collapse collapse_post friction
  friction_post)
for s in "${stages[@]}"; do
  "stage_$s"
done
wait_ok
echo "dem_reference: done"
