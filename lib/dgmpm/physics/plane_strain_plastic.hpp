#pragma once
// 2D plane strain with J2 plasticity (docs/method.md, "Solids that yield"): sigma = C : (eps -
// eps_p), eps_p deviatoric (eps_p_zz = -(eps_p_xx + eps_p_yy), nonzero), back stress
// X = (2/3) C_kin eps_p, yield function f = sigma_eq(s - X) - (sigma_y + H_iso p) with
// sigma_eq(a) = sqrt(3/2 a : a). The DGMPM step is plane strain's (fluxes with the elastic
// moduli), then each particle returns over the whole step. With eps_zz = 0,
// sigma_zz = nu (sigma_xx + sigma_yy) - E eps_p_zz exactly (the elastic step's increment
// nu (d sigma_xx + d sigma_yy), the return's -2 mu d eps_p_zz): it is derived from the in-plane
// stresses and eps_p_zz, never stored apart.

#include "plane_strain.hpp"
#include "plastic_flow.hpp"

#include <array>
#include <cmath>

namespace dgmpm {

struct PlaneStrainPlastic : PlaneStrain {
  // The plastic strain tensor (tensor components, xy not doubled), the equivalent plastic strain
  // p, and the energy the returns dissipated per unit mass (accumulated).
  static constexpr int n_internal = 6;
  enum Internal {
    exx = 0,
    eyy = 1,
    exy = 2,
    ezz = 3,
    equivalent_plastic_strain = 4,
    dissipation = 5
  };
  static constexpr std::array<const char*, n_internal> internal_names{
      "eps_p_xx", "eps_p_yy", "eps_p_xy", "eps_p_zz", "plastic_strain", "dissipation"};
  static constexpr std::array<const char*, n_internal> internal_units{"1", "1", "1",
                                                                      "1", "1", "J/kg"};

  class Material : public PlaneStrain::Material {
   public:
    Material() = default;
    Material(double young, double poisson, double density, const PlasticFlow& flow = {})
        : PlaneStrain::Material(young, poisson, density), flow(flow) {}
    Material(const PlaneStrain::Material& elastic, const PlasticFlow& flow = {})
        : PlaneStrain::Material(elastic), flow(flow) {}
    PlasticFlow flow;
  };

  // A cell's material only sets its fluxes (elastic moduli); each particle returns with its own.
  static Material blend(const Material& a, double ma, const Material& b, double mb) {
    return Material(PlaneStrain::blend(a, ma, b, mb));
  }

  // sigma_zz of a physical state with its plastic strain.
  template <class Z>
  static double sigma_zz(const State& physical_state, const Material& m, const Z& z) {
    return PlaneStrain::sigma_zz(physical_state, m) - m.young * z[ezz];
  }

  // Output columns derived from a particle (physical state, internal variables, material):
  // sigma_zz, the von Mises stress sigma_eq(s), the back stress X = (2/3) C_kin eps_p.
  static constexpr std::array<const char*, 6> derived_names{"sigma_zz",       "von_mises",
                                                            "back_stress_xx", "back_stress_yy",
                                                            "back_stress_xy", "back_stress_zz"};
  static constexpr std::array<const char*, 6> derived_units{"Pa", "Pa", "Pa", "Pa", "Pa", "Pa"};
  template <class Z>
  static std::array<double, 6> derived(const State& s, const Z& z, const Material& m) {
    const double zz = sigma_zz(s, m, z), mean = (s[sxx] + s[syy] + zz) / 3;
    const double a = s[sxx] - mean, b = s[syy] - mean, c = zz - mean;
    const double eq = std::sqrt(1.5 * (a * a + b * b + c * c + 2 * s[sxy] * s[sxy]));
    const double k = 2.0 / 3.0 * m.flow.kinematic_hardening;
    return {zz, eq, k * z[exx], k * z[eyy], k * z[exy], k * z[ezz]};
  }

  // The strain tensor, elastic (the compliance of the stress with its sigma_zz) plus plastic:
  // eps_zz = 0 up to round-off, as plane strain asks.
  template <class Z>
  static Eigen::Matrix3d strain_tensor(const State& s, const Z& z, const Material& m) {
    Eigen::Matrix3d sigma = stress_tensor_3d(s, m, z);
    sigma(2, 2) = sigma_zz(s, m, z);  // with the plastic strain's share
    Eigen::Matrix3d e = physics::isotropic_strain(sigma, m.lambda(), m.mu());
    e(0, 0) += z[exx];
    e(1, 1) += z[eyy];
    e(0, 1) += z[exy];
    e(1, 0) += z[exy];
    e(2, 2) += z[ezz];
    return e;
  }

  // The return of particle state q (specific) and internal variables z over dt: radial in the
  // deviatoric plane of s - X, dp from PlasticFlow with the stiffness 3 mu + h.
  template <class Q, class Z>
  static void particle_step(Q&& q, Z&& z, const Material& m, double dt) {
    const PlasticFlow& flow = m.flow;
    if (flow.elastic()) return;
    const double rho = m.density, mu = m.mu();
    const double sx = q[sxx] * rho, sy = q[syy] * rho, sxy_ = q[sxy] * rho;
    const double sz = m.poisson * (sx + sy) - m.young * z[ezz];
    const double mean = (sx + sy + sz) / 3, ck = 2.0 / 3.0 * flow.kinematic_hardening;
    const double xx = sx - mean - ck * z[exx], yy = sy - mean - ck * z[eyy];
    const double zz = sz - mean - ck * z[ezz], xy = sxy_ - ck * z[exy];
    const double eq = std::sqrt(1.5 * (xx * xx + yy * yy + zz * zz + 2 * xy * xy));
    const double p = z[equivalent_plastic_strain];
    const double f_trial = eq - flow.yield_radius(p);
    if (!(f_trial > 0)) return;
    const double dp = flow.increment(f_trial, 3 * mu + flow.hardening(), dt);
    const double k = 1.5 * dp / eq;  // d eps_p = k (s - X)
    z[exx] += k * xx;
    z[eyy] += k * yy;
    z[ezz] += k * zz;
    z[exy] += k * xy;
    z[equivalent_plastic_strain] = p + dp;
    const double eq_after = eq - (3 * mu + flow.kinematic_hardening) * dp;
    z[dissipation] += flow.dissipation(eq_after, p + dp, dp) / rho;
    q[sxx] = (sx - 2 * mu * k * xx) / rho;
    q[syy] = (sy - 2 * mu * k * yy) / rho;
    q[sxy] = (sxy_ - 2 * mu * k * xy) / rho;
  }

  // sigma : C^-1 : sigma / (2 rho), sigma_zz included: plane strain's in-plane energy plus
  // E eps_p_zz^2 / 2 (sigma_zz's distance from nu (sigma_xx + sigma_yy), squared, over 2 E).
  template <class Z>
  static double elastic_energy_per_mass(const State& q, const Z& z, const Material& m) {
    return PlaneStrain::elastic_energy_per_mass(q, m) + 0.5 * m.young * z[ezz] * z[ezz] / m.density;
  }
  // Without the internal variables it would miss sigma_zz's part: not offered.
  static double elastic_energy_per_mass(const State&, const Material&) = delete;
  static double energy_per_mass(const State&, const Material&) = delete;

  // Energy per unit mass stored by hardening: (H_iso p^2 / 2 + C_kin eps_p : eps_p / 3) / rho.
  template <class Z>
  static double stored_energy_per_mass(const Z& z, const Material& m) {
    const double ee = z[exx] * z[exx] + z[eyy] * z[eyy] + z[ezz] * z[ezz] + 2 * z[exy] * z[exy];
    return m.flow.stored_energy(z[equivalent_plastic_strain], ee) / m.density;
  }
  template <class Z>
  static double dissipated_energy_per_mass(const Z& z) {
    return z[dissipation];
  }
};

}  // namespace dgmpm
