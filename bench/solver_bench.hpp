#pragma once
#include <ostream>
#include <string>
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

// Distributed scaling (under mpirun; one rank otherwise): the 2D plate (DCU Euler, 1 particle per
// cell) of each total particle count over the launched ranks; one JSON line per count with the
// slowest rank's time per step (best batch), particle-steps per second, the imbalance, and the
// halo's time, bytes and messages per step and its ghost particles (largest over the ranks).
void run_scaling_benchmark(std::ostream& out, const std::vector<int>& particle_counts,
                           double seconds);

// The speed goals as JSON, on one core unless said: each case's particle-steps per second (min and
// median of `repeats` runs of `seconds`), heap bytes per particle, the bytes a particle-step must
// move by count, the triad bandwidth measured in the same run and the fraction of the bound it
// gives, the arithmetic peak measured in the same run and, given `flop_counts` (the JSON of
// bench/count_flops.py; none when empty), each case's roofline; then two threads against one
// (speed-up, identical states).
void run_goals_benchmark(std::ostream& out, int particles, double seconds, int repeats,
                         const std::string& flop_counts);

// The goal cases' names, in the order --json reports them.
std::vector<std::string> goal_case_names();
// Builds the goal case `name` at `particles` particles, takes one step, then `steps` steps inside
// a function of their own (count_flops.py's callgrind counts only those). Throws
// std::runtime_error for an unknown name, listing the cases.
void run_counted_steps(const std::string& name, int particles, int steps);

}  // namespace dgmpm::bench
