#!/usr/bin/env bash
# Fuzzes skidsim's parsers with libFuzzer under AddressSanitizer and
# UndefinedBehaviorSanitizer. Installs clang, its runtime (libFuzzer, the
# sanitizers) and the packages the configure needs (idempotent; as root, or
# through sudo), configures and builds ./build-fuzz (clang, SKIDSIM_FUZZ=ON;
# ./build is untouched), then runs each harness of fuzz/ in turn for SECONDS
# (default 60), seeded with the shipped files.
#
#   scripts/fuzz.sh                        # every harness, 60 s each
#   scripts/fuzz.sh 300 exercise lcm_log   # these two, 300 s each
#
# Harnesses: exercise operator_script soil_table loader_params loader_urdf
# control lcm_log heightmap. The corpus grows in build-fuzz/corpus/HARNESS from run to
# run; each run's output is in build-fuzz/logs/HARNESS.log; a finding (crash,
# sanitizer report, an exception other than io::InputError, an InputError
# naming no file) is written to build-fuzz/artifacts/HARNESS-crash-* and makes
# the script exit 1. Reproduce one with: build-fuzz/fuzz/fuzz_HARNESS FILE
set -euo pipefail
cd "$(dirname "$0")/.."

SECONDS_EACH=60
if [[ $# -gt 0 && $1 =~ ^[0-9]+$ ]]; then
  SECONDS_EACH=$1
  shift
fi
ALL=(exercise operator_script soil_table loader_params loader_urdf control lcm_log heightmap)
if (($#)); then HARNESSES=("$@"); else HARNESSES=("${ALL[@]}"); fi

source scripts/packages.sh
install_packages fuzz "${SKIDSIM_PACKAGES[@]}" \
  clang-14 \
  libclang-rt-14-dev `# libFuzzer and the sanitizer runtimes` \
  llvm-14            `# llvm-symbolizer: stacks with file and line`

B=build-fuzz
cmake -S . -B "$B" -DCMAKE_CXX_COMPILER=clang++-14 -DCMAKE_BUILD_TYPE=RelWithDebInfo \
  -DSKIDSIM_FUZZ=ON -DSKIDSIM_BUILD_TESTS=OFF >/dev/null
cmake --build "$B" --target skidsim_fuzzers -j"$(nproc)"

# Seeds: the shipped files, and binary ones for the LCM harnesses.
seeds() {
  case $1 in
    exercise) ls scenarios/*.xml | grep -v '\.operator\.xml$' ;;
    operator_script) ls scenarios/*.operator.xml ;;
    soil_table) echo assets/soils.xml ;;
    loader_params) echo assets/loader/skidsteer.params.xml ;;
    loader_urdf) echo assets/loader/skidsteer.urdf ;;
  esac
}
rm -rf "$B/seeds" "$B/dict"
mkdir -p "$B/seeds" "$B/dict" "$B/corpus" "$B/artifacts" "$B/logs"
"$B/fuzz/fuzz_make_seeds" "$B/seeds/control" "$B/seeds/lcm_log" "$B/seeds/heightmap"
for h in exercise operator_script soil_table loader_params loader_urdf; do
  mkdir -p "$B/seeds/$h"
  seeds "$h" | while read -r f; do cp "$f" "$B/seeds/$h/"; done
  # A dictionary: the seeds' element and attribute names, and values that
  # test the number parsing.
  {
    seeds "$h" | xargs cat | grep -oE '<[A-Za-z_]+' | sort -u | sed 's/.*/"&"/'
    seeds "$h" | xargs cat | grep -oE ' [A-Za-z_]+="' | sort -u | sed 's/"/\\"/g; s/.*/"&"/'
    printf '"%s"\n' '/>' '</' '<!--' '-->' 'nan' 'inf' '-inf' '-1e309' '1e400' '0x1p3' '-0' '&amp;' '&#0;'
  } >"$B/dict/$h.dict"
done

export ASAN_OPTIONS=${ASAN_OPTIONS:-abort_on_error=1:detect_leaks=1}
export UBSAN_OPTIONS=${UBSAN_OPTIONS:-print_stacktrace=1:halt_on_error=1}
export ASAN_SYMBOLIZER_PATH=${ASAN_SYMBOLIZER_PATH:-/usr/lib/llvm-14/bin/llvm-symbolizer}

status=0
summary=()
for h in "${HARNESSES[@]}"; do
  bin="$B/fuzz/fuzz_$h"
  [[ -x $bin ]] || { echo "fuzz: no harness '$h' (${ALL[*]})" >&2; exit 2; }
  mkdir -p "$B/corpus/$h"
  dict=()
  [[ -f $B/dict/$h.dict ]] && dict=(-dict="$B/dict/$h.dict")
  echo "fuzz: $h for ${SECONDS_EACH} s"
  if "$bin" "$B/corpus/$h" "$B/seeds/$h" "${dict[@]}" -max_total_time="$SECONDS_EACH" -timeout=30 \
      -max_len=16384 -print_final_stats=1 -artifact_prefix="$B/artifacts/$h-" >"$B/logs/$h.log" 2>&1; then
    result=ok
  else
    result="FINDING (see $B/logs/$h.log, $B/artifacts/$h-*)"
    status=1
  fi
  runs=$(grep -oE '^stat::number_of_executed_units: *[0-9]+' "$B/logs/$h.log" | grep -oE '[0-9]+$' || true)
  cov=$(grep -oE 'cov: [0-9]+ ft: [0-9]+ corp: [0-9]+' "$B/logs/$h.log" | tail -1 || true)
  summary+=("$h: ${runs:-?} runs, ${cov:-no coverage line}: $result")
done
printf 'fuzz: %s\n' "${summary[@]}"
exit $status
