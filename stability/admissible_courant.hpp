#pragma once
// The admissible Courant number of a cell layout (docs/method.md, "Stability"): what `dgmpm
// courant` prints and what the automatic time step uses.

#include "stability/courant_search.hpp"
#include "stability/layout.hpp"
#include "stability/one_step_map.hpp"
#include "stability/options.hpp"

#include <algorithm>
#include <cmath>
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

// A growth budget (docs/method.md, "The growth budget"): the largest time step such that no
// Fourier mode of the layout's symbol grows by more than `factor` over the run. Per step, the
// growth max_theta rho - 1 may be ln(factor) / N, N the run's steps: `horizon` of them, or, with
// `crossings`, horizon / C (horizon counts the times the fastest wave crosses a cell, the steps
// at Courant 1). Never more than kGrowthCap per step: strong instabilities are not budgeted.
inline constexpr double kGrowthCap = 1e-4;
// Growth per step at 1.01 times the L2 limit above which the limit is an instability's onset,
// kept as it is: the budget extends only weak growth (round-off level just above the limit).
inline constexpr double kOnsetGrowth = 1e-9;
struct GrowthBudget {
  double factor = 1.1;
  double horizon = 1000;
  bool crossings = false;
  // Growth per step allowed at Courant number C.
  double allowance(double courant) const {
    const double steps = crossings ? horizon / courant : horizon;
    return std::min(kGrowthCap, std::log(factor) / steps);
  }
};

struct BudgetedCourant {
  double courant = 0.0;   // the largest C <= max(1, strict) such that every C' in (0, C] passes
                          // L2 or the budget
  double strict = 0.0;    // the L2 criterion's C*
  double growth = 0.0;    // max rho - 1 at `courant` (<= the allowance there); 0 when the L2
                          // limit is kept (where it is within the L2 tolerance)
  bool bounded = true;    // the L2 result's (false: nothing failed up to its maximum)
  bool extended = false;  // above the L2 limit: the layout is weakly unstable
  int evaluations = 0;    // growth evaluations
};

// The budgeted Courant number from the L2 result `strict` of the same map. Above the L2 limit a C
// passes when its growth is within the budget; a layout whose L2 limit is the onset of an
// instability (growth above kOnsetGrowth or the allowance just above it) keeps the L2 limit.
BudgetedCourant budgeted_courant(const OneStepMap& map, const CourantResult& strict,
                                 const GrowthBudget& budget);
BudgetedCourant budgeted_courant(const CellLayout& layout, const AnalysisSetting& setting,
                                 const GrowthBudget& budget);

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
