#pragma once
// The finite-strain tests' own statement of the uniaxial laws (steel; independent of
// hyperelastic_laws.hpp's forms) and the bisection their exact solutions are found with.

#include <cmath>
#include <functional>

namespace dgmpm::test {

inline constexpr double kYoung = 2e11, kPoisson = 0.3, kRho0 = 7800;
inline const double kLambda = kYoung * kPoisson / ((1 + kPoisson) * (1 - 2 * kPoisson));
inline const double kMu = kYoung / (2 * (1 + kPoisson));
inline const double kM = kLambda + 2 * kMu, kKappa = kLambda + 2 * kMu / 3;

// Saint Venant-Kirchhoff in uniaxial strain: P = (M/2) F (F^2 - 1).
inline double svk_stress(double f) {
  return 0.5 * kM * f * (f * f - 1);
}
inline double svk_tangent(double f) {
  return 0.5 * kM * (3 * f * f - 1);
}
// Neo-Hookean with F = diag(f, 1, 1): J = f, tr(F^T F) = f^2 + 2.
inline double nh_energy(double f) {
  return 0.5 * kMu * (std::cbrt(1 / (f * f)) * (f * f + 2) - 3) + 0.5 * kKappa * (f - 1) * (f - 1);
}
inline double nh_stress(double f) {
  return 2 * kMu / 3 * std::pow(f, -5.0 / 3) * (f * f - 1) + kKappa * (f - 1);
}
inline double nh_tangent(double f) {
  return 2 * kMu / 9 * std::pow(f, -8.0 / 3) * (f * f + 5) + kKappa;
}

// The root of g on [a, b] (g(a), g(b) of opposite signs), to round-off.
inline double bisect(const std::function<double(double)>& g, double a, double b) {
  double ga = g(a);
  for (int k = 0; k < 200; ++k) {
    const double m = 0.5 * (a + b), gm = g(m);
    if (m == a || m == b) break;
    if ((gm > 0) == (ga > 0)) {
      a = m;
      ga = gm;
    } else {
      b = m;
    }
  }
  return 0.5 * (a + b);
}

}  // namespace dgmpm::test
