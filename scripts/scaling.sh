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
{
  for n in 1 2 4; do echo "strong $(run $n "$strong")"; done
  for n in 1 2 4; do echo "weak $(run $n $((weak * n)))"; done
} | python3 -c '
import json, sys
cores = int(sys.argv[1])
rows = [(line.split(" ", 1)[0], json.loads(line.split(" ", 1)[1])) for line in sys.stdin]
base = {}
print(f"{\"kind\":6} {\"ranks\":>5} {\"particles\":>10} {\"s/step\":>10} {\"p-steps/s\":>10} "
      f"{\"efficiency\":>10} {\"halo s/step\":>11} {\"halo B/step\":>11} {\"msgs\":>4} "
      f"{\"imbalance\":>9}")
for kind, r in rows:
    n = r["ranks"]
    if n == 1:
        base[kind] = r
    b = base[kind]
    # Strong: speed-up over ranks; weak: time per step held.
    eff = (b["seconds_per_step"] / r["seconds_per_step"] / n if kind == "strong"
           else b["seconds_per_step"] / r["seconds_per_step"])
    note = "  (oversubscribed: %d ranks on %d cores)" % (n, cores) if n > cores else ""
    print(f"{kind:6} {n:5d} {r[\"particles\"]:10.0f} {r[\"seconds_per_step\"]:10.4g} "
          f"{r[\"particle_steps_per_second\"]:10.3g} {eff:10.2f} "
          f"{r.get(\"halo_seconds_per_step\", 0):11.3g} {r.get(\"halo_bytes_sent_per_step\", 0):11.0f} "
          f"{r.get(\"messages_per_step\", 0):4.0f} {r[\"imbalance\"]:9.3f}{note}")
' "$cores"
