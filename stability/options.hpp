#pragma once
// The choices of an analysis: time scheme, criterion, model.

#include <dgmpm/time_integration.hpp>

#include <string>

namespace dgmpm::stability {

using dgmpm::TimeScheme;  // lib's: the analysis steps with lib's integrators
using dgmpm::to_string;
enum class Criterion { l2, monotone };
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

}  // namespace dgmpm::stability
