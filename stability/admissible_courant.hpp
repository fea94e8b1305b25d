#pragma once
// The admissible Courant number of a cell layout (docs/method.md, "Stability"): what `dgmpm
// courant` prints and what the automatic time step uses.

#include "stability/courant_search.hpp"
#include "stability/layout.hpp"
#include "stability/one_step_map.hpp"
#include "stability/options.hpp"

#include <string>

namespace dgmpm::stability {

struct CourantResult {
  double courant = 0.0;  // C* = c dt / dx, to SearchOptions::courant_tolerance (1e-9 by default)
  bool bounded = true;   // false: nothing failed up to SearchOptions::max_courant
  // What fails first, at failing_courant, just above C*:
  double failing_courant = 0.0;
  std::string direction;  // failing wave family: "+x", "-x" ("both" if the map did not decouple)
  double critical_theta = 0;    // L2: wavenumber in [0, pi] of the first failing Fourier mode
  double critical_theta_y = 0;  // 2D: its y wavenumber, in (-pi, pi]
  int limiting_particle = -1;   // monotone: index into the layout's positions
  int evaluations = 0;          // criterion evaluations of the search
};

// Scan step, tolerance and margin tolerance of each criterion.
SearchOptions default_search_options(Criterion criterion);

CourantResult admissible_courant(const OneStepMap& map, Criterion criterion,
                                 const SearchOptions& options);

// The entry point: builds the one-step map from lib's integrator and searches. Throws
// std::invalid_argument for an invalid layout.
CourantResult admissible_courant(const CellLayout& layout, TimeScheme scheme, Criterion criterion,
                                 Model model = Model::elastic);
// Any dimension. 2D elastic: L2 only (the system does not split into scalar waves, which the
// monotone criterion needs): std::invalid_argument for monotone.
CourantResult admissible_courant(const CellLayout& layout, const AnalysisSetting& setting,
                                 Criterion criterion);

}  // namespace dgmpm::stability
