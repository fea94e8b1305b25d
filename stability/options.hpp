#pragma once
// The choices of an analysis: time scheme, criterion, model.

#include <dgmpm/dg_operator.hpp>
#include <dgmpm/discretisation.hpp>
#include <dgmpm/time_integration.hpp>

#include <string>

namespace dgmpm::stability {

using dgmpm::TimeScheme;  // lib's: the analysis steps with lib's integrators
using dgmpm::to_string;
// l2: von Neumann; monotone: no new extrema; budget: l2, or above the l2 limit a growth within a
// growth budget (admissible_courant.hpp, GrowthBudget), what the automatic time step uses.
enum class Criterion { l2, monotone, budget };
// advection: u_t + a u_x = 0, a > 0 (waves to +x); elastic: the 1D bar (waves both ways).
enum class Model { advection, elastic };

const char* to_string(Criterion);
const char* to_string(Model);

// Inverse of to_string; throw std::invalid_argument listing the accepted names.
TimeScheme parse_time_scheme(const std::string&);
Criterion parse_criterion(const std::string&);
Model parse_model(const std::string&);

// Degree in the Courant number of the one-step map: 1 for Euler, 2 for RK2 (I + L + L^2 / 2).
int polynomial_degree(TimeScheme);

using dgmpm::FluxScheme;
using dgmpm::Formulation;

// What the analysis steps: the model problem of a periodic grid of identical cells.
// 1D: unit cells, unit wave speed (advection speed 1, waves to +x; elastic bar E = rho = 1).
// 2D: cells dx / dy = aspect with min(dx, dy) = 1; advection with speeds (a, b) >= 0,
// C = dt max(a / dx, b / dy); plane strain with Poisson's ratio nu and c_p = 1,
// C = c_p dt / min(dx, dy).
struct AnalysisSetting {
  int dim = 1;
  TimeScheme time = TimeScheme::euler;
  FluxScheme flux = FluxScheme::dcu;  // 2D
  Model model = Model::elastic;
  double poisson = 0.3;               // 2D elastic
  double speed_x = 1.0, speed_y = 0;  // 2D advection
  double aspect = 1.0;                // 2D: dx / dy
  // The scheme's formulation (lib's discretisation.hpp); in the periodic model the consistent one
  // differs from the paper's for 2D layouts whose mass is not centred along an axis and, with RK2,
  // layouts with a node holding less than a fifth of its cell's mass.
  Formulation formulation = Formulation::consistent;
};

// Degree in C of the one-step map: 1 (Euler) or 2 (RK2), times 2 for CTU, whose operator holds
// dt itself (transverse corrections scale with dt / h).
int polynomial_degree(const AnalysisSetting&);

}  // namespace dgmpm::stability
