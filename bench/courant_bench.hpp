#pragma once
#include <iosfwd>

namespace dgmpm::bench {

// Median time of one admissible-Courant query (1D, N <= 4 particles per cell, each criterion and
// time scheme, elastic model) and the time of a 100 x 100 two-particle map (`dgmpm courant
// --map 100`). Goals: under 1 ms per query, under 10 s for the map on one core.
void run_courant_benchmark(std::ostream& out);

// 2D queries: 1, 2, 4 and 9 particles, Euler and RK2, DCU and CTU, L2 and monotone (advection),
// advection and plane strain; min and median of `repeats` runs.
void run_courant_2d_benchmark(std::ostream& out, int repeats);

}  // namespace dgmpm::bench
