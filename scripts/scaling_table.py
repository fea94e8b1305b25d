#!/usr/bin/env python3
"""Formats scripts/scaling.sh's lines ("strong|weak JSON" from `dgmpm bench --what scaling`) as a
table: efficiency is the speed-up over one rank divided by the ranks (strong) or one rank's time
per step over this one's (weak); ranks above the cores are marked oversubscribed."""
import json
import sys

cores = int(sys.argv[1])
rows = [(line.split(" ", 1)[0], json.loads(line.split(" ", 1)[1])) for line in sys.stdin if line.strip()]
print("%-6s %5s %10s %10s %10s %10s %11s %11s %4s %9s" % ("kind", "ranks", "particles", "s/step",
      "p-steps/s", "efficiency", "halo s/step", "halo B/step", "msgs", "imbalance"))
base = {}
for kind, r in rows:
    n = r["ranks"]
    if n == 1:
        base[kind] = r
    b = base[kind]
    ratio = b["seconds_per_step"] / r["seconds_per_step"]
    efficiency = ratio / n if kind == "strong" else ratio
    note = "  (oversubscribed: %d ranks on %d cores)" % (n, cores) if n > cores else ""
    print("%-6s %5d %10.0f %10.4g %10.3g %10.2f %11.3g %11.0f %4.0f %9.3f%s" % (
        kind, n, r["particles"], r["seconds_per_step"], r["particle_steps_per_second"], efficiency,
        r.get("halo_seconds_per_step", 0), r.get("halo_bytes_sent_per_step", 0),
        r.get("messages_per_step", 0), r["imbalance"], note))
