"""bench/count_flops.py counts what it says: the floating-point operations a run executes.

1. Exactly, on a kernel of known work compiled here (the compiler free to vectorise it): per
   element y = a x + y (2 flops) and s += sqrt(x) / (1 + y) (4 flops); scalar and packed
   instructions, a square root and a division, counted only inside the toggled function.
2. Against a count by hand of the 1D DGMPM Euler step (one particle per cell, periodic bar), kernel
   by kernel from lib/ (per cell = per particle-step):
     project_cell         15  (m q: 2, outer product with S and sum: 8, S: 1, times 1/m_i: 4)
     stiffness             0  (the lattice's cells share one layout: computed once per build;
                               the cells whose located coordinates are a few bits off it
                               compute their own, 26 each: the counted total sits above 88)
     add_volume_term      18  (specific flux: 2, 2x2 by 2x2 product: 12, sum: 4)
     faces                30  (edge states 2 + 2, Riemann solve 16 (1 / (2 Z) precomputed), two
                               fluxes 6, sums 4)
     update               10  (per node dt / m_i: 1, then 2 multiply-adds of 2)
     interpolate_cell      7  (S: 1, 2x2 by 2: 6)
     finiteness check      8  (0 * block, summed)
     total                88
   within 5%: a count that missed a stage or double counted one would not be.
3. The count is per step: over two steps and over four (beyond the first two, which count_flops
   takes off) the same flops per particle-step.
valgrind is a test dependency (scripts/setup.sh --tests installs it)."""
import json
import os
import shutil
import subprocess
import sys
import tempfile

binary, source, compiler = sys.argv[1:4]
sys.path.insert(0, os.path.join(source, "bench"))
import count_flops  # noqa: E402

if not shutil.which("valgrind"):
    print("bench_flop_count: valgrind is missing (scripts/setup.sh --tests installs it)")
    sys.exit(1)

KERNEL = r"""
#include <cmath>
#include <cstdio>
#include <vector>
__attribute__((noinline)) double kernel(const double* x, double* __restrict y, int n, double a) {
  double s = 0;
  for (int i = 0; i < n; ++i) y[i] = a * x[i] + y[i];
  for (int i = 0; i < n; ++i) s += std::sqrt(x[i]) / (1.0 + y[i]);
  return s;
}
int main(int argc, char**) {
  const int n = 1000 + argc;  // not known to the compiler
  std::vector<double> x(n, 2.0), y(n, 1.0);
  double s = 0;
  for (int k = 0; k < 10; ++k) s += kernel(x.data(), y.data(), n, 0.5);
  std::printf("%d %g\n", n, s);
}
"""

with tempfile.TemporaryDirectory() as work:
    src = os.path.join(work, "kernel.cpp")
    exe = os.path.join(work, "kernel")
    with open(src, "w") as f:
        f.write(KERNEL)
    subprocess.run([compiler, "-O3", "-o", exe, src], check=True)
    table = count_flops.disassemble(exe)
    flops, total, arithmetic, packed, outside, out = count_flops.counted(exe, table, [], "kernel*",
                                                                        work)
    n = int(out.split()[0])
    expected = 10 * 6 * n
    print("kernel: %d flops counted, %d expected (%d arithmetic instructions, %d packed)"
          % (flops, expected, arithmetic, packed))
    assert flops == expected, (flops, expected)
    assert 0 < arithmetic <= expected and total > arithmetic, (arithmetic, total)

    table = count_flops.disassemble(binary)
    per_step = {}
    for steps in (2, 4):
        per_step[steps] = count_flops.count_case(binary, table, "1D DGMPM Euler", 4000, steps,
                                                 work)["flops_per_particle_step"]
    print("1D DGMPM Euler: %.2f flops per particle-step over 2 steps, %.2f over 4; 88 by hand"
          % (per_step[2], per_step[4]))
    assert abs(per_step[4] - per_step[2]) <= 0.005 * per_step[2], per_step
    assert 0.95 * 88 <= per_step[4] <= 1.05 * 88, per_step

# The counts feed bench --json's roofline; a file without every case is refused up front.
with tempfile.TemporaryDirectory() as work:
    partial = os.path.join(work, "counts.json")
    with open(partial, "w") as f:
        json.dump({"cases": {"1D DGMPM Euler": {"flops_per_particle_step": 116,
                                                "instructions_per_particle_step": 600}}}, f)
    refused = subprocess.run([binary, "bench", "--json", "--particles", "1000", "--seconds",
                              "0.01", "--repeats", "1", "--flop-counts", partial],
                             capture_output=True, text=True)
    assert refused.returncode != 0, refused
    assert 'has no case "1D DGMPM RK2"' in refused.stderr, refused.stderr
    assert refused.stdout == "", refused.stdout
print("bench_flop_count: passed")
