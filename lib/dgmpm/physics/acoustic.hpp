#pragma once
// The acoustic tensor of a plane-strain hyperelastic tangent and what the finite-strain physics
// need of it (docs/method.md, "Finite strain"): along a unit normal N, A_ik = A_iJkL N_J N_L; the
// impedance tensor Z = sqrt(rho0 A), the symmetric root (closed form in 2 x 2), which links the
// traction and velocity jumps of the waves crossing a face normal to N; and the largest wave speed
// over in-plane directions, sqrt(lambda_max(A(N)) / rho0), which has no closed form.

#include "hyperelastic_laws.hpp"

#include <Eigen/Core>
#include <algorithm>
#include <array>
#include <cmath>
#include <limits>

namespace dgmpm {

inline Eigen::Matrix2d acoustic_tensor(const PlaneTangent& a, const Eigen::Vector2d& n) {
  Eigen::Matrix2d q = Eigen::Matrix2d::Zero();
  for (int i = 0; i < 2; ++i)
    for (int k = 0; k < 2; ++k)
      for (int J = 0; J < 2; ++J)
        for (int L = 0; L < 2; ++L) q(i, k) += a[i][J][k][L] * n[J] * n[L];
  return q;
}

// sqrt(rho0 A) for a symmetric A, the symmetric positive root: for a 2 x 2 positive definite B,
// sqrt(B) = (B + sqrt(det B) I) / sqrt(tr B + 2 sqrt(det B)) (Cayley-Hamilton). NaN entries when A
// is not positive definite (no real speed).
inline Eigen::Matrix2d impedance_tensor(const Eigen::Matrix2d& acoustic, double rho0) {
  const Eigen::Matrix2d b = rho0 * acoustic;
  const double det = b(0, 0) * b(1, 1) - b(0, 1) * b(1, 0);
  if (!(det > 0 && b(0, 0) > 0))
    return Eigen::Matrix2d::Constant(std::numeric_limits<double>::quiet_NaN());
  const double root = std::sqrt(det);
  return (b + root * Eigen::Matrix2d::Identity()) / std::sqrt(b.trace() + 2 * root);
}

namespace detail {

// The acoustic tensor along N = (cos t, sin t) as a function of phi = 2 t: each entry is
// x0 + x1 cos phi + x2 sin phi (N_J N_L = (delta_JL + ...) / 2), so its eigenvalues are
// m(phi) +- r(phi), r = sqrt(d^2 + o^2), with m = (A_xx + A_yy) / 2, d = (A_xx - A_yy) / 2,
// o = A_xy each of that form.
struct DirectionalForm {
  Eigen::Vector3d m, d, o;
};
inline DirectionalForm directional_form(const PlaneTangent& a) {
  const auto entry = [&](int i, int k) {
    return Eigen::Vector3d(0.5 * (a[i][0][k][0] + a[i][1][k][1]),
                           0.5 * (a[i][0][k][0] - a[i][1][k][1]),
                           0.5 * (a[i][0][k][1] + a[i][1][k][0]));
  };
  const Eigen::Vector3d xx = entry(0, 0), yy = entry(1, 1);
  return {0.5 * (xx + yy), 0.5 * (xx - yy), 0.5 * (entry(0, 1) + entry(1, 0))};
}

// The largest of g(phi) = sign m(phi) + r(phi) over phi: sampled at 16 angles (the eigenvalues'
// maxima and minima are smooth and broad: m, d and o are single harmonics, and r, the distance
// to the origin of a point on an ellipse, has corners at its minima only), then each sampled
// local maximum refined by Newton's method on g' kept inside its bracket, to round-off.
inline double largest_over_directions(const DirectionalForm& f, double sign) {
  constexpr int kSamples = 16;
  constexpr double step = 2 * M_PI / kSamples;
  static const auto table = [] {
    std::array<std::array<double, 2>, kSamples> t;
    for (int k = 0; k < kSamples; ++k) t[k] = {std::cos(k * step), std::sin(k * step)};
    return t;
  }();
  const Eigen::Vector3d m = sign * f.m;
  std::array<double, kSamples> g;
  for (int k = 0; k < kSamples; ++k) {
    const double c = table[k][0], s = table[k][1];
    const double d = f.d[0] + f.d[1] * c + f.d[2] * s, o = f.o[0] + f.o[1] * c + f.o[2] * s;
    g[k] = m[0] + m[1] * c + m[2] * s + std::sqrt(d * d + o * o);
  }
  const auto [least, most] = std::minmax_element(g.begin(), g.end());
  double best = *most;
  // Flat to round-off (an isotropic state: every direction alike): the samples hold the maximum.
  if (*most - *least <= 1e-14 * std::abs(*most)) return best;
  for (int k = 0; k < kSamples; ++k) {
    // A sampled local maximum, strictly above its left neighbour (one per plateau of equal
    // samples).
    if (!(g[k] > g[(k + kSamples - 1) % kSamples]) || g[k] < g[(k + 1) % kSamples]) continue;
    double lo = (k - 1) * step, hi = (k + 1) * step, phi = k * step;
    for (int it = 0; it < 60; ++it) {
      const double c = std::cos(phi), s = std::sin(phi);
      // x(phi), x'(phi); x''(phi) = x0 - x(phi).
      const double mv = m[0] + m[1] * c + m[2] * s, m1 = -m[1] * s + m[2] * c;
      const double dv = f.d[0] + f.d[1] * c + f.d[2] * s, d1 = -f.d[1] * s + f.d[2] * c;
      const double ov = f.o[0] + f.o[1] * c + f.o[2] * s, o1 = -f.o[1] * s + f.o[2] * c;
      const double r = std::sqrt(dv * dv + ov * ov);
      best = std::max(best, mv + r);
      if (!(r > 0)) break;  // isotropic: every direction alike
      const double dot = dv * d1 + ov * o1;
      const double g1 = m1 + dot / r;
      const double g2 = (m[0] - mv) +
                        (d1 * d1 + dv * (f.d[0] - dv) + o1 * o1 + ov * (f.o[0] - ov)) / r -
                        dot * dot / (r * r * r);
      (g1 > 0 ? lo : hi) = phi;
      double next = phi - g1 / g2;
      if (!(g2 < 0) || !(next > lo && next < hi)) next = 0.5 * (lo + hi);
      // Newton converges quadratically: a step below 1e-8 leaves g within 1e-16 of its maximum.
      if (std::abs(next - phi) <= 1e-8 || hi - lo <= 1e-8) break;
      phi = next;
    }
  }
  return best;
}

// A lower bound of the smallest eigenvalue over directions: m's least value less the largest r
// can reach (|x0| + |(x1, x2)| for d and o).
inline double smallest_eigenvalue_bound(const DirectionalForm& f) {
  const double d = std::abs(f.d[0]) + std::hypot(f.d[1], f.d[2]);
  const double o = std::abs(f.o[0]) + std::hypot(f.o[1], f.o[2]);
  return f.m[0] - std::hypot(f.m[1], f.m[2]) - std::hypot(d, o);
}

}  // namespace detail

// The largest wave speed over in-plane directions, sqrt(max_N lambda_max(A(N)) / rho0), to
// round-off; NaN when A(N) is not positive definite for some direction (its smallest eigenvalue's
// minimum over directions, found the same way, is not positive).
inline double max_wave_speed(const PlaneTangent& a, double rho0) {
  const detail::DirectionalForm f = detail::directional_form(a);
  if (!(detail::smallest_eigenvalue_bound(f) > 0) &&
      !(-detail::largest_over_directions(f, -1.0) > 0))
    return std::numeric_limits<double>::quiet_NaN();
  return std::sqrt(detail::largest_over_directions(f, 1.0) / rho0);
}

}  // namespace dgmpm
