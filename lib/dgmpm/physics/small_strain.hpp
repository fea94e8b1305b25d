#pragma once
// The small strain of an isotropic linear elastic solid from its stress (3 x 3, tensor
// components): eps = (sigma - lambda / (3 lambda + 2 mu) tr(sigma) I) / (2 mu), the inverse of
// sigma = lambda tr(eps) I + 2 mu eps. Output only: the scheme evolves stresses, not strains.

#include <Eigen/Core>

namespace dgmpm::physics {

// -1 < nu < 1/2: the range of an isotropic elasticity tensor that is positive definite (shear and
// bulk moduli E / (2 (1 + nu)) and E / (3 (1 - 2 nu)) positive for E > 0).
inline bool admissible_poisson(double nu) {
  return nu > -1 && nu < 0.5;
}

inline Eigen::Matrix3d isotropic_strain(const Eigen::Matrix3d& sigma, double lambda, double mu) {
  const double volumetric = lambda / (3 * lambda + 2 * mu) * sigma.trace();
  return (sigma - volumetric * Eigen::Matrix3d::Identity()) / (2 * mu);
}

}  // namespace dgmpm::physics
