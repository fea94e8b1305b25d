#pragma once
// Hyperelastic laws for finite strain (docs/method.md, "Finite strain"), as compile-time
// parameters of a finite-strain physics: the strain energy W(F) per unit reference volume, the
// nominal stress P = dW/dF and its tangent dP/dF. So far their uniaxial-strain forms,
// F = diag(F, 1, 1), with P the xx component (the 1D physics, finite_strain_bar.hpp).
//   Saint Venant-Kirchhoff: W = (lambda/2) (tr E)^2 + mu E : E, E = (F^T F - I) / 2; uniaxially
//     W = (M/8) (F^2 - 1)^2, P = (M/2) F (F^2 - 1), M = lambda + 2 mu: hyperbolic for
//     F > 1/sqrt(3) only (dP/dF = (M/2) (3 F^2 - 1)).
//   Neo-Hookean: W = (mu/2) (J^(-2/3) tr(F^T F) - 3) + (kappa/2) (J - 1)^2, J = det F,
//     kappa = lambda + 2 mu / 3; uniaxially P = (2 mu / 3) F^(-5/3) (F^2 - 1) + kappa (F - 1),
//     dP/dF = (2 mu / 9) F^(-8/3) (F^2 + 5) + kappa, positive for every F > 0.
// Both reduce to small-strain elasticity with the Lame moduli at F = I (dP/dF = M).
// Uniaxially the Cauchy stress is diag(P, s_l, s_l): sigma_xx = P F / J = P, and the lateral
// s_l = sigma_yy = sigma_zz (uniaxial_lateral_stress; SVK lambda (F^2 - 1) / (2 F), neo-Hookean
// mu F^(-5/3) (1 - F^2) / 3 + kappa (F - 1)). `uniaxial_lowest_f`: where the longitudinal
// tangent vanishes (the hyperbolic range is F above it).

#include <cmath>

namespace dgmpm {

// The Lame moduli of a law, from Young's modulus and Poisson's ratio.
struct LameModuli {
  double lambda = 0, mu = 0;
  static LameModuli from_young(double young, double poisson) {
    return {young * poisson / ((1 + poisson) * (1 - 2 * poisson)), young / (2 * (1 + poisson))};
  }
  double p_modulus() const { return lambda + 2 * mu; }
};

struct SaintVenantKirchhoff {
  static constexpr const char* name = "saint_venant_kirchhoff";
  static double uniaxial_energy(double f, const LameModuli& k) {
    const double g = f * f - 1;
    return 0.125 * k.p_modulus() * g * g;
  }
  static double uniaxial_stress(double f, const LameModuli& k) {
    return 0.5 * k.p_modulus() * f * (f * f - 1);
  }
  static double uniaxial_tangent(double f, const LameModuli& k) {
    return 0.5 * k.p_modulus() * (3 * f * f - 1);
  }
  static double uniaxial_lateral_stress(double f, const LameModuli& k) {
    return 0.5 * k.lambda * (f * f - 1) / f;
  }
  static double uniaxial_lowest_f() { return 1 / std::sqrt(3.0); }
};

struct NeoHookean {
  static constexpr const char* name = "neo_hookean";
  static double bulk(const LameModuli& k) { return k.lambda + 2.0 * k.mu / 3.0; }
  static double uniaxial_energy(double f, const LameModuli& k) {
    const double j = f;
    return 0.5 * k.mu * (std::pow(j, -2.0 / 3.0) * (f * f + 2) - 3) +
           0.5 * bulk(k) * (j - 1) * (j - 1);
  }
  static double uniaxial_stress(double f, const LameModuli& k) {
    return 2.0 * k.mu / 3.0 * std::pow(f, -5.0 / 3.0) * (f * f - 1) + bulk(k) * (f - 1);
  }
  static double uniaxial_tangent(double f, const LameModuli& k) {
    return 2.0 * k.mu / 9.0 * std::pow(f, -8.0 / 3.0) * (f * f + 5) + bulk(k);
  }
  static double uniaxial_lateral_stress(double f, const LameModuli& k) {
    return k.mu / 3.0 * std::pow(f, -5.0 / 3.0) * (1 - f * f) + bulk(k) * (f - 1);
  }
  static double uniaxial_lowest_f() { return 0.0; }
};

}  // namespace dgmpm
