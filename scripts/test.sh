#!/usr/bin/env bash
# Builds dgmpm in Release with the tests and runs the whole suite through ctest.
set -euo pipefail
cd "$(dirname "$0")/.."
[ "${DGMPM_SKIP_SETUP:-0}" = 1 ] || bash scripts/setup.sh --tests
cmake -S . -B build -DCMAKE_BUILD_TYPE=Release -DDGMPM_MPI=ON -DBUILD_TESTING=ON >/dev/null
cmake --build build -j"$(nproc)"
cd build && ctest --output-on-failure -j"$(nproc)"
