#pragma once
// Admissible Courant number over a grid of two-particle layouts (`dgmpm courant --map N`).

#include "stability/options.hpp"

#include <vector>

namespace dgmpm::stability {

// c[i * n + j]: C* of the layout {(i + 1/2) / n, (j + 1/2) / n} with the given masses (two
// relative weights, or none for equal). With equal masses the map is symmetric and each pair is
// analysed once.
std::vector<double> two_particle_courant_map(int n, const std::vector<double>& masses,
                                             TimeScheme scheme, Criterion criterion, Model model);

}  // namespace dgmpm::stability
