#pragma once
// The acoustic tensor of a plane-strain hyperelastic tangent and what the finite-strain physics
// need of it (docs/method.md, "Finite strain"): along a unit normal N, A_ik = A_iJkL N_J N_L; the
// impedance tensor Z = sqrt(rho0 A), the symmetric root (by eigen-decomposition), which links the
// traction and velocity jumps of the waves crossing a face normal to N; and the largest wave speed
// over in-plane directions, sqrt(lambda_max(A(N)) / rho0), which has no closed form.

#include "hyperelastic_laws.hpp"

#include <Eigen/Core>
#include <Eigen/Eigenvalues>
#include <algorithm>
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

// sqrt(rho0 A) for a symmetric A; NaN entries when A is not positive definite (no real speed).
inline Eigen::Matrix2d impedance_tensor(const Eigen::Matrix2d& acoustic, double rho0) {
  const Eigen::SelfAdjointEigenSolver<Eigen::Matrix2d> eig(acoustic);
  if (!(eig.eigenvalues().minCoeff() > 0))
    return Eigen::Matrix2d::Constant(std::numeric_limits<double>::quiet_NaN());
  return eig.eigenvectors() * (rho0 * eig.eigenvalues()).cwiseSqrt().asDiagonal() *
         eig.eigenvectors().transpose();
}

// The largest wave speed over in-plane directions N = (cos t, sin t): A(-N) = A(N), so t in
// [0, pi), sampled at 72 angles, the best bracket then narrowed by golden-section search to 1e-12
// of pi. NaN when A is not positive definite at some sampled angle.
inline double max_wave_speed(const PlaneTangent& a, double rho0) {
  constexpr int kAngles = 72;
  const auto eigenvalues = [&](double t) {
    const Eigen::Matrix2d q = acoustic_tensor(a, Eigen::Vector2d(std::cos(t), std::sin(t)));
    const double mean = 0.5 * q.trace(), half = std::hypot(0.5 * (q(0, 0) - q(1, 1)), q(0, 1));
    return Eigen::Vector2d(mean - half, mean + half);
  };
  const double step = M_PI / kAngles;
  int best = 0;
  double largest = -1;
  for (int s = 0; s < kAngles; ++s) {
    const Eigen::Vector2d e = eigenvalues(s * step);
    if (!(e[0] > 0)) return std::numeric_limits<double>::quiet_NaN();
    if (e[1] > largest) largest = e[1], best = s;
  }
  // The maximum lies within one step of the best sample (lambda_max is smooth in t, with period
  // pi and at most two maxima).
  const double ratio = 0.5 * (std::sqrt(5.0) - 1);
  double lo = (best - 1) * step, hi = (best + 1) * step;
  double x1 = hi - ratio * (hi - lo), x2 = lo + ratio * (hi - lo);
  double f1 = eigenvalues(x1)[1], f2 = eigenvalues(x2)[1];
  while (hi - lo > 1e-12 * M_PI) {
    if (f1 < f2) {
      lo = x1, x1 = x2, f1 = f2;
      x2 = lo + ratio * (hi - lo);
      f2 = eigenvalues(x2)[1];
    } else {
      hi = x2, x2 = x1, f2 = f1;
      x1 = hi - ratio * (hi - lo);
      f1 = eigenvalues(x1)[1];
    }
  }
  return std::sqrt(std::max({largest, f1, f2}) / rho0);
}

}  // namespace dgmpm
