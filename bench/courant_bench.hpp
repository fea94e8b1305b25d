#pragma once
#include <iosfwd>

namespace dgmpm::bench {

// Median time of one admissible-Courant query (1D, N <= 4 particles per cell, each criterion and
// time scheme, elastic model) and the time of a 100 x 100 two-particle map (`dgmpm courant
// --map 100`). Goals: under 1 ms per query, under 10 s for the map on one core.
void run_courant_benchmark(std::ostream& out);

}  // namespace dgmpm::bench
