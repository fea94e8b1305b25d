"""`dgmpm bench --json` prints one JSON object with every goal case, its rates (min <= median,
one per repeat), heap bytes per particle, the bytes a particle-step moves by count, the triad
bandwidth and the fraction of its bound, the arithmetic peak and, given flop counts, each case's
roofline (all consistent with each other), and two threads against one with identical states.
Speed itself is not asserted (benchmarks, not tests)."""
import json
import os
import subprocess
import sys
import tempfile

binary = sys.argv[1]
names = subprocess.run([binary, "bench", "--cases"], check=True, capture_output=True,
                       text=True).stdout.splitlines()
# Counts per particle-step in bench/count_flops.py's form (made up here: the roofline's arithmetic
# is what is checked; tests/bench_flop_count.py checks the counting).
counts = {name: {"flops_per_particle_step": 100.0 + k, "instructions_per_particle_step": 500.0 + k}
          for k, name in enumerate(names)}
with tempfile.NamedTemporaryFile("w", suffix=".json", delete=False) as f:
    json.dump({"cases": counts}, f)
try:
    out = subprocess.run([binary, "bench", "--json", "--particles", "3000", "--seconds", "0.01",
                          "--repeats", "2", "--threads", "2", "--flop-counts", f.name], check=True,
                         capture_output=True, text=True).stdout
finally:
    os.unlink(f.name)
report = json.loads(out)
triad = report["triad_bytes_per_second"]
assert triad > 1e8, triad
peak = report["arithmetic_peak_flops_per_second"]
assert peak["build"] > 1e8 and peak["fma"] >= 0, peak
assert report["flop_counts"] == f.name, report["flop_counts"]
assert names == [c["case"] for c in report["cases"]], names
for c in report["cases"]:
    r, median = c["roofline"], c["particle_steps_per_second"]["median"]
    count = counts[c["case"]]
    assert r["flops_per_particle_step"] == count["flops_per_particle_step"], r
    assert abs(r["flops_per_second"] - r["flops_per_particle_step"] * median) <= 1e-12 * r["flops_per_second"], r
    assert abs(r["instructions_per_second"] - count["instructions_per_particle_step"] * median) <= 1e-9 * r["instructions_per_second"], r
    assert abs(r["fraction_of_peak"] - r["flops_per_second"] / peak["build"]) <= 1e-12, r
    assert abs(r["arithmetic_intensity"] - r["flops_per_particle_step"] / c["bytes_per_particle_step"]) <= 1e-12, r
    arithmetic = peak["build"] / r["flops_per_particle_step"]
    memory = c["bound_particle_steps_per_second"]
    assert r["binding_bound"] == ("arithmetic" if arithmetic <= memory else "memory"), r
    assert abs(r["fraction_of_binding_bound"] - median / min(arithmetic, memory)) <= 1e-12, r
    assert peak["fma"] == 0 or abs(r["fraction_of_fma_peak"] - r["flops_per_second"] / peak["fma"]) <= 1e-12, r
assert names == ["1D DGMPM Euler", "1D DGMPM RK2", "1D moving, auto dt, 2 ppc",
                 "2D DGMPM DCU Euler, 1 ppc", "2D DGMPM CTU RK2, 1 ppc",
                 "2D DGMPM 4 ppc (DCU Euler)", "2D MPM USL, 1 ppc",
                 "2D DGMPM CTU Euler, 1 ppc", "2D DGMPM CTU Euler, 4 ppc",
                 "2D plastic DCU Euler, 1 ppc", "2D plastic DCU Euler, 4 ppc",
                 "2D plastic CTU Euler, 1 ppc", "2D plastic CTU Euler, 4 ppc",
                 "2D every particle returns, DCU Euler, 1 ppc",
                 "2D every particle returns, CTU Euler, 1 ppc",
                 "2D every particle returns, n = 4.37, DCU Euler, 1 ppc",
                 "2D finite strain neo-Hookean DCU Euler, 1 ppc",
                 "2D finite strain SVK DCU Euler, 1 ppc"], names
for c in report["cases"]:
    rates = c["particle_steps_per_second"]
    assert len(rates["runs"]) == 2 and min(rates["runs"]) == rates["min"], c
    assert 0 < rates["min"] <= rates["median"], c
    assert c["threads"] == 1, c
    assert c["bytes_per_particle_step"] >= 56, c
    assert abs(c["bound_particle_steps_per_second"] * c["bytes_per_particle_step"] - triad) <= 1e-6 * triad, c
    assert abs(c["fraction_of_bound"] - rates["median"] / c["bound_particle_steps_per_second"]) <= 1e-12, c
    assert 0 < c["resident_bytes_per_particle"] < 1e5, c
    assert 0 <= c["yielded_share"] <= 1, c
    # Only the plastic plates yield, some of their particles within the timed steps, and every
    # particle of the plates made to return at every step.
    plastic = c["case"].startswith("2D plastic") or c["case"].startswith("2D every")
    assert (c["yielded_share"] > 0) == plastic, c
    assert c["yielded_share"] == 1 or not c["case"].startswith("2D every"), c
median = {c["case"]: c["particle_steps_per_second"]["median"] for c in report["cases"]}
costs = report["plastic_step_cost"]
assert [p["case"] for p in costs] == [n for n in names
                                      if n.startswith("2D plastic") or n.startswith("2D every")], costs
for p in costs:
    assert p["elastic"] in median and "plastic" not in p["elastic"], p
    assert abs(p["cost"] - median[p["elastic"]] / median[p["case"]]) <= 1e-12 * p["cost"], p
finite = report["finite_strain_step_cost"]
assert [p["case"] for p in finite] == [n for n in names if n.startswith("2D finite strain")], finite
for p in finite:
    assert p["small_strain"] == "2D DGMPM DCU Euler, 1 ppc", p
    assert abs(p["cost"] - median[p["small_strain"]] / median[p["case"]]) <= 1e-12 * p["cost"], p
assert [t["case"] for t in report["two_threads"]] == names, report["two_threads"]
assert all(t["bit_identical"] for t in report["two_threads"]), report["two_threads"]
refused = subprocess.run([binary, "bench", "--json", "--what", "solver"], capture_output=True)
assert refused.returncode != 0 and b"--what excludes --json" in refused.stderr, refused
unknown = subprocess.run([binary, "bench", "--count-steps", "3D DGMPM Euler"], capture_output=True,
                         text=True)
assert unknown.returncode != 0 and unknown.stdout == "", unknown
assert 'no goal case "3D DGMPM Euler"; allowed: "1D DGMPM Euler", ' in unknown.stderr, unknown.stderr
print("bench --json: %d cases, triad %.3g B/s" % (len(names), triad))
