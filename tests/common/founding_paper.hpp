#pragma once
// Parameters of the founding paper's two-bar impact (method.md 6), shared by the solver tests.

#include <cmath>

namespace dgmpm::test {

inline const double E = 2e11, rho = 7800;
inline const double c = std::sqrt(E / rho), Z = std::sqrt(E * rho);
inline const double v0 = 4e9 / (2 * Z);  // sigma = 4e9 in the founding document
inline const double dx = 0.04;           // 150 cells over the two 3 m bars

}  // namespace dgmpm::test
