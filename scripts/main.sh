#!/usr/bin/env bash
# Installs the dependencies, builds in Release and runs the main job: the founding paper's
# two-bar impact (scenes/two_bar_impact.json), printing its error against the exact solution.
set -euo pipefail
cd "$(dirname "$0")/.."
[ "${DGMPM_SKIP_SETUP:-0}" = 1 ] || bash scripts/setup.sh
cmake -S . -B build -DCMAKE_BUILD_TYPE=Release -DDGMPM_MPI=ON >/dev/null
cmake --build build -j"$(nproc)" --target dgmpm  # the binary only, not the test programs
build/bin/dgmpm run "$@"
