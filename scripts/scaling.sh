#!/usr/bin/env bash
# Strong and weak scaling of the distributed step on this machine: `dgmpm bench --what scaling`
# (2D plate, DCU Euler, one particle per cell, one thread per rank) under `mpirun -np N` for
# N = 1, 2 and 4; 4 ranks oversubscribe a 2-core machine (two ranks per core), which the table
# says. Strong: the same total particles on every N. Weak: the same particles per rank.
#   bash scripts/scaling.sh [build/bin/dgmpm] [strong total] [weak per rank] [seconds]
set -euo pipefail
cd "$(dirname "$0")/.."
binary=${1:-build/bin/dgmpm}
strong=${2:-1000000}
weak=${3:-250000}
seconds=${4:-3}
export OMPI_ALLOW_RUN_AS_ROOT=1 OMPI_ALLOW_RUN_AS_ROOT_CONFIRM=1  # CI containers run as root
cores=$(nproc)
run() {  # ranks, particles
  mpiexec -np "$1" --oversubscribe --bind-to none "$binary" bench --what scaling --threads 1 \
    --particles "$2" --seconds "$seconds"
}
lines=$(
  for n in 1 2 4; do echo "strong $(run $n "$strong")"; done
  for n in 1 2 4; do echo "weak $(run $n $((weak * n)))"; done
)
printf '%s\n' "$lines"
printf '%s\n' "$lines" | /usr/bin/python3 scripts/scaling_table.py "$cores"
