#pragma once
// The plastic part of a step (docs/method.md, "Solids that yield"): J2 flow with linear isotropic
// and kinematic hardening, rate-independent or Perzyna viscoplastic, integrated over a whole step
// from the elastic trial state by backward Euler. Whatever the stress space (uniaxial stress,
// plane strain), the return reduces to one scalar: the equivalent plastic strain increment dp,
// from the trial overstress f_trial = sigma_eq(trial) - (sigma_y + H_iso p) and the stiffness k
// the return sees (E + h for the bar, 3 mu + h in 3D stress spaces, h = H_iso + C_kin).

#include <algorithm>
#include <cmath>
#include <limits>

namespace dgmpm {

struct PlasticFlow {
  double yield_stress = std::numeric_limits<double>::infinity();  // sigma_y; infinite: elastic
  double isotropic_hardening = 0;                                 // H_iso
  double kinematic_hardening = 0;                                 // C_kin
  double relaxation_time = 0;                                     // tau; 0: rate-independent
  double rate_exponent = 1;                                       // n

  // The ranges the return is derived for; a scene outside them is refused. Softening (a negative
  // hardening modulus) makes the local problem ill-posed; Newton's descent needs a convex rate law.
  static bool admissible_hardening(double modulus) { return modulus >= 0; }
  static bool admissible_rate_exponent(double n) { return n >= 1; }

  bool elastic() const { return !(yield_stress < std::numeric_limits<double>::infinity()); }
  double hardening() const { return isotropic_hardening + kinematic_hardening; }  // h
  // The radius of the elastic domain after an equivalent plastic strain p.
  double yield_radius(double p) const { return yield_stress + isotropic_hardening * p; }

  // Energy per unit volume stored by hardening after an equivalent plastic strain p, with
  // eps_p_squared = eps_p : eps_p (tensor): H_iso p^2 / 2 + C_kin eps_p : eps_p / 3, the back
  // stress being (2/3) C_kin eps_p (the bar's X = C_kin eps_p is the same with eps_p = eps_p_xx (1,
  // -1/2, -1/2), eps_p : eps_p = 3/2 eps_p_xx^2).
  double stored_energy(double p, double eps_p_squared) const {
    if (elastic()) return 0.0;
    return 0.5 * isotropic_hardening * p * p + kinematic_hardening * eps_p_squared / 3;
  }
  // Energy per unit volume a return of dp dissipates: (sigma_y + the viscous overstress) dp from
  // the end-of-step values, the radius sigma_eq(s - X) after the return less H_iso p.
  double dissipation(double radius_after, double p_after, double dp) const {
    return (radius_after - isotropic_hardening * p_after) * dp;
  }

  // dp >= 0 of a return from the trial overstress f_trial (> 0) with stiffness k over dt.
  // Rate-independent: f_trial / k (the overstress after the return is 0). Perzyna,
  // dp / dt = <f / sigma_y>^n / tau with f = f_trial - k dp at the end of the step: in the
  // overstress after the return, y = f / sigma_y, the root of the convex increasing
  // g(y) = (dt / tau) y^n + (sigma_y / k) y - f_trial / k. Newton from the smaller of two points
  // where g >= 0 (y = f_trial / sigma_y, and the root of the power term alone) descends
  // monotonically onto the root, in a few iterations even at dt / tau = 1e20; it stops when a
  // step no longer lowers y (round-off). For n = 1 (the usual choice) g is linear and its root
  // closed, dp = f_trial / (k + sigma_y tau / dt) (no pow in the hot loop; finite for any tau/dt).
  double increment(double f_trial, double k, double dt) const {
    if (!(f_trial > 0)) return 0.0;
    if (!(relaxation_time > 0)) return f_trial / k;
    const double ratio = dt / relaxation_time, n = rate_exponent, sy = yield_stress;
    if (n == 1) return f_trial / (k + sy / ratio);
    const auto g = [&](double y) { return ratio * std::pow(y, n) + (sy / k) * y - f_trial / k; };
    double y = std::min(f_trial / sy, std::pow(f_trial / (k * ratio), 1.0 / n));
    for (int iteration = 0; iteration < 200; ++iteration) {
      const double value = g(y);
      if (!(value > 0)) break;  // on the root, to round-off
      const double slope = ratio * n * std::pow(y, n - 1) + sy / k;
      const double next = y - value / slope;
      if (!(next < y)) break;  // no progress: round-off
      y = std::max(next, 0.0);
    }
    return std::max(0.0, (f_trial - sy * y) / k);
  }
};

}  // namespace dgmpm
