#pragma once
// 1D uniaxial strain with J2 plasticity (docs/method.md, "Solids that yield"): a plane wave along
// x, eps_xx the only strain. The state is the bar's, (sigma_xx / rho, v), with the P-wave modulus
// lambda + 2 mu as its modulus (the elastic step is the bar's with it); sigma_yy = sigma_zz follow
// from sigma_xx and the plastic strain (eps_p = eps_p_xx (1, -1/2, -1/2), deviatoric):
// sigma_yy = lambda (sigma_xx + 2 mu eps_p_xx) / (lambda + 2 mu) + mu eps_p_xx. The yield
// function f = sigma_eq(s - X) - (sigma_y + H_iso p) reduces to |sigma_xx - sigma_yy - C_kin
// eps_p_xx| - (sigma_y + H_iso p). The same wave as the plane-strain strip periodic along y.

#include "elastic_bar.hpp"
#include "plastic_flow.hpp"
#include "small_strain.hpp"

#include <array>
#include <cmath>

namespace dgmpm {

struct UniaxialStrainPlastic : ElasticBar {
  static constexpr int n_internal = 3;
  enum Internal { plastic_strain = 0, equivalent_plastic_strain = 1, dissipation = 2 };
  static constexpr std::array<const char*, n_internal> internal_names{"eps_p_xx", "plastic_strain",
                                                                      "dissipation"};
  static constexpr std::array<const char*, n_internal> internal_units{"1", "1", "J/kg"};

  // The bar's material with the P-wave modulus as its `young`, and the Lame moduli.
  class Material : public ElasticBar::Material {
   public:
    Material() = default;
    Material(double young, double poisson, double density, const PlasticFlow& flow = {})
        : ElasticBar::Material(young * (1 - poisson) / ((1 + poisson) * (1 - 2 * poisson)),
                               density),
          flow(flow), lambda_(young * poisson / ((1 + poisson) * (1 - 2 * poisson))),
          mu_(young / (2 * (1 + poisson))) {}
    explicit Material(const ElasticBar::Material& elastic) : ElasticBar::Material(elastic) {}
    double lambda() const { return lambda_; }
    double mu() const { return mu_; }
    PlasticFlow flow;

   private:
    double lambda_ = 0, mu_ = 0;
  };

  // A cell's material only sets its fluxes (the P-wave modulus); each particle returns with its
  // own.
  static Material blend(const Material& a, double ma, const Material& b, double mb) {
    return Material(ElasticBar::blend(a, ma, b, mb));
  }

  // sigma_yy (= sigma_zz) of a particle.
  template <class Z>
  static double sigma_yy(double sigma_xx, const Z& z, const Material& m) {
    const double e = z[plastic_strain];
    return m.lambda() * (sigma_xx + 2 * m.mu() * e) / m.young + m.mu() * e;
  }

  template <class Q, class Z>
  static void particle_step(Q&& q, Z&& z, const Material& m, double dt) {
    const PlasticFlow& flow = m.flow;
    if (flow.elastic()) return;
    const double sigma = q[0] * m.density, e = z[plastic_strain], mu = m.mu();
    const double xi = sigma - sigma_yy(sigma, z, m) - flow.kinematic_hardening * e;
    const double p = z[equivalent_plastic_strain];
    const double f_trial = std::abs(xi) - flow.yield_radius(p);
    if (!(f_trial > 0)) return;
    const double dp = flow.increment(f_trial, 3 * mu + flow.hardening(), dt);
    const double direction = xi >= 0 ? 1.0 : -1.0;
    z[plastic_strain] = e + dp * direction;
    z[equivalent_plastic_strain] = p + dp;
    const double radius_after = std::abs(xi) - (3 * mu + flow.kinematic_hardening) * dp;
    z[dissipation] += flow.dissipation(radius_after, p + dp, dp) / m.density;
    q[0] = (sigma - 2 * mu * dp * direction) / m.density;
  }

  // Output columns derived from a particle: sigma_yy (= sigma_zz), the von Mises stress
  // |sigma_xx - sigma_yy| and the back stress X_xx = (2/3) C_kin eps_p_xx.
  static constexpr std::array<const char*, 3> derived_names{"sigma_yy", "von_mises",
                                                            "back_stress_xx"};
  static constexpr std::array<const char*, 3> derived_units{"Pa", "Pa", "Pa"};
  template <class Z>
  static std::array<double, 3> derived(const State& s, const Z& z, const Material& m) {
    const double yy = sigma_yy(s[0], z, m);
    return {yy, std::abs(s[0] - yy), 2.0 / 3.0 * m.flow.kinematic_hardening * z[plastic_strain]};
  }

  // sigma : C^-1 : sigma / (2 rho) with sigma = diag(sigma_xx, sigma_yy, sigma_yy).
  template <class Z>
  static double elastic_energy_per_mass(const State& q, const Z& z, const Material& m) {
    const double l = m.lambda(), mu = m.mu();
    const double young = mu * (3 * l + 2 * mu) / (l + mu), nu = l / (2 * (l + mu));
    const double sx = q[0] * m.density, sy = sigma_yy(sx, z, m);
    return (sx * sx + 2 * sy * sy - 2 * nu * (2 * sx * sy + sy * sy)) / (2 * young * m.density);
  }
  static double elastic_energy_per_mass(const State&, const Material&) = delete;
  static double energy_per_mass(const State&, const Material&) = delete;

  // (H_iso p^2 / 2 + C_kin eps_p : eps_p / 3) / rho, eps_p : eps_p = 3/2 eps_p_xx^2.
  template <class Z>
  static double stored_energy_per_mass(const Z& z, const Material& m) {
    const double e = z[plastic_strain];
    return m.flow.stored_energy(z[equivalent_plastic_strain], 1.5 * e * e) / m.density;
  }
  template <class Z>
  static double dissipated_energy_per_mass(const Z& z) {
    return z[dissipation];
  }

  // The strain tensor, elastic (the isotropic compliance of sigma = diag(sigma_xx, sigma_yy,
  // sigma_yy)) plus plastic (eps_p_xx (1, -1/2, -1/2)): eps_yy = eps_zz = 0 up to round-off.
  template <class Z>
  static Eigen::Matrix3d strain_tensor(const State& s, const Z& z, const Material& m) {
    const double yy = sigma_yy(s[0], z, m), e = z[plastic_strain];
    return physics::isotropic_strain(Eigen::Vector3d(s[0], yy, yy).asDiagonal(), m.lambda(),
                                     m.mu()) +
           Eigen::Matrix3d(Eigen::Vector3d(e, -e / 2, -e / 2).asDiagonal());
  }
};

}  // namespace dgmpm
