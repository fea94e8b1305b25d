#pragma once
#include <ostream>
#include <vector>

namespace dgmpm::bench {
// Particle-steps per second of DGMPM (Euler, RK2; fixed and moving particles, moving with
// "courant": "auto") and MPM USL on a periodic bar with one particle per cell, for each particle
// count; then the cost per particle of the automatic time step (operator rebuild, dt with a warm
// cache, full step) and the layouts the moving auto run analysed.
void run_solver_benchmark(std::ostream& out, const std::vector<int>& particle_counts,
                          double seconds);
// The 2D plate scaled to each particle count: DCU and CTU, Euler and RK2, 1 and 4 particles per
// cell; particle-steps per second and heap bytes per particle.
void run_plate_benchmark(std::ostream& out, const std::vector<int>& particle_counts,
                         double seconds);

}  // namespace dgmpm::bench
