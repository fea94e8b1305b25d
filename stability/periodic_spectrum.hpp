#pragma once
// The global one-step operator of a periodic grid of identical cells, and its von Neumann
// counterpart: the two must agree (test of the whole-scene route against the local one).

#include "stability/arpack_spectrum.hpp"
#include "stability/layout.hpp"
#include "stability/one_step_map.hpp"
#include "stability/options.hpp"

namespace dgmpm::stability {

// Spectral radius, by ARPACK, of one step of lib's integrator on `cells` periodic cells each
// holding the layout (dx = 1, unit wave speed, dt = courant).
double periodic_grid_spectral_radius(const CellLayout& layout, TimeScheme scheme, Model model,
                                     int cells, double courant, const ArpackOptions& options = {});

// max over the grid's wavenumbers theta_k = 2 pi k / cells of rho(G(theta_k)).
double discrete_von_neumann_radius(const OneStepMap& map, int cells, double courant);

}  // namespace dgmpm::stability
