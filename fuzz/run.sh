#!/usr/bin/env bash
# Builds the libFuzzer targets with clang (every target instrumented: libFuzzer coverage,
# AddressSanitizer, UndefinedBehaviorSanitizer) and runs each for SECONDS seconds from its seed
# corpus (scenes/ for the scene parser, fuzz/corpus/courant for the courant options) with its
# dictionary. Fails on any finding; the crashing input is left in WORK/findings.
#   fuzz/run.sh [--seconds 30] [--work DIR] [--seed N] [--jobs N]
# The test suite runs it for 30 s per target with a fixed seed (ctest -R fuzz).
set -euo pipefail
root="$(cd "$(dirname "$0")/.." && pwd)"
seconds=30
work="$root/build-fuzz"
seed=0
jobs="$(nproc)"
while [ $# -gt 0 ]; do
  case "$1" in
    --seconds) seconds="$2"; shift 2 ;;
    --work) work="$2"; shift 2 ;;
    --seed) seed="$2"; shift 2 ;;
    --jobs) jobs="$2"; shift 2 ;;
    *) echo "fuzz/run.sh: unknown option $1" >&2; exit 2 ;;
  esac
done
command -v clang++ >/dev/null || { echo "fuzz/run.sh: clang++ not found (apt-get install clang)" >&2; exit 2; }
# -O1 and line tables only (the sanitizers' usual flags): the instrumented build of the solver's
# templates takes 2.5x less time than at -O2 -g, and reports still name file and line.
CC=clang CXX=clang++ cmake -S "$root" -B "$work/build" -DDGMPM_FUZZ=ON -DBUILD_TESTING=OFF \
  -DCMAKE_BUILD_TYPE=None -DCMAKE_CXX_FLAGS="-O1 -gline-tables-only -DNDEBUG" >/dev/null
cmake --build "$work/build" -j"$jobs" --target fuzz_scene fuzz_courant_options
mkdir -p "$work/corpus/scene" "$work/corpus/courant_options" "$work/findings"
status=0
run() {  # target, dictionary, seed corpus, max input length
  local target="$1" dict="$2" seeds="$3" max_len="$4"
  echo "== $target: $seconds s"
  # The first corpus directory receives the new inputs: a work directory, never the sources.
  ( cd "$root" && "$work/build/bin/$target" -max_total_time="$seconds" -seed="$seed" \
      -dict="$dict" -max_len="$max_len" -timeout=20 -rss_limit_mb=2048 -print_final_stats=1 \
      -artifact_prefix="$work/findings/$target-" "$work/corpus/${target#fuzz_}" "$seeds" ) \
    2>&1 | tee "$work/$target.log" | grep -E "^(INFO: Seed|Done|stat::|fuzz_.* reach|==[0-9]+==|SUMMARY)" \
    || true
  [ "${PIPESTATUS[0]}" = 0 ] || status=1
  # The fuzzer must reach past validation: valid inputs (and, for scenes, stepped runs).
  local reach
  reach="$(grep -E "^$target reach" "$work/$target.log" || true)"
  case "$target" in
    fuzz_scene) [[ "$reach" =~ \ ([1-9][0-9]*)\ valid.*\ ([1-9][0-9]*)\ stepped ]] || { echo "$target: no valid scene stepped" >&2; status=1; } ;;
    *) [[ "$reach" =~ \ ([1-9][0-9]*)\ accepted ]] || { echo "$target: no input accepted" >&2; status=1; } ;;
  esac
}
run fuzz_scene "$root/fuzz/scene.dict" "$root/scenes" 8192
run fuzz_courant_options "$root/fuzz/courant.dict" "$root/fuzz/corpus/courant" 512
exit $status
