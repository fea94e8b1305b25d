#pragma once
// 1D elasto-plastic and elasto-viscoplastic bar, uniaxial stress (docs/method.md, "Solids that
// yield"): sigma = E (eps - eps_p), yield function f = |sigma - X| - (sigma_y + H_iso p) with the
// back stress X = C_kin eps_p. The DGMPM step is the elastic bar's (fluxes with the elastic
// moduli); the particle step then returns each particle's trial stress over the whole step
// (fractional step). A linear elastic material is one with an infinite yield stress, so elastic
// and plastic materials share a scene.

#include "elastic_bar.hpp"
#include "plastic_flow.hpp"

#include <array>
#include <cmath>

namespace dgmpm {

struct ElastoPlasticBar : ElasticBar {
  // Internal variables: plastic strain eps_p, equivalent plastic strain p, and the energy the
  // returns dissipated per unit mass (accumulated, for the energy balance).
  static constexpr int n_internal = 3;
  enum Internal { plastic_strain = 0, equivalent_plastic_strain = 1, dissipation = 2 };
  static constexpr std::array<const char*, n_internal> internal_names{"eps_p", "plastic_strain",
                                                                      "dissipation"};
  static constexpr std::array<const char*, n_internal> internal_units{"1", "1", "J/kg"};

  class Material : public ElasticBar::Material {
   public:
    Material() = default;
    Material(double young, double density, const PlasticFlow& flow = {})
        : ElasticBar::Material(young, density), flow(flow) {}
    Material(const ElasticBar::Material& elastic, const PlasticFlow& flow = {})
        : ElasticBar::Material(elastic), flow(flow) {}
    PlasticFlow flow;
  };

  // A cell's material only sets its fluxes (elastic moduli); each particle returns with its own.
  static Material blend(const Material& a, double ma, const Material& b, double mb) {
    return Material(ElasticBar::blend(a, ma, b, mb));
  }

  // The return of particle state q (specific: sigma / rho, v) and internal variables z over dt.
  // Velocities are untouched; sigma, eps_p, p and the dissipation change.
  template <class Q, class Z>
  static void particle_step(Q&& q, Z&& z, const Material& m, double dt) {
    const PlasticFlow& flow = m.flow;
    if (flow.elastic()) return;
    const double sigma = q[0] * m.density, back = flow.kinematic_hardening * z[plastic_strain];
    const double f_trial = std::abs(sigma - back) - flow.yield_radius(z[equivalent_plastic_strain]);
    if (!(f_trial > 0)) return;
    const double dp = flow.increment(f_trial, m.young + flow.hardening(), dt);
    const double direction = sigma - back >= 0 ? 1.0 : -1.0;
    const double sigma_new = sigma - m.young * dp * direction;
    z[plastic_strain] += dp * direction;
    z[equivalent_plastic_strain] += dp;
    const double radius_after = std::abs(sigma_new - flow.kinematic_hardening * z[plastic_strain]);
    z[dissipation] += flow.dissipation(radius_after, z[equivalent_plastic_strain], dp) / m.density;
    q[0] = sigma_new / m.density;
  }

  // Output columns derived from a particle (physical state, internal variables, material).
  static constexpr std::array<const char*, 1> derived_names{"back_stress"};
  static constexpr std::array<const char*, 1> derived_units{"Pa"};
  template <class Z>
  static std::array<double, 1> derived(const State&, const Z& z, const Material& m) {
    return {m.flow.kinematic_hardening * z[plastic_strain]};
  }

  // The axial strain, elastic and plastic: sigma / E + eps_p.
  template <class Z>
  static Eigen::Matrix3d strain_tensor(const State& s, const Z& z, const Material& m) {
    Eigen::Matrix3d e = ElasticBar::strain_tensor(s, z, m);
    e(0, 0) += z[plastic_strain];
    return e;
  }

  // Energy per unit mass stored by hardening: (H_iso p^2 + C_kin eps_p^2) / (2 rho).
  template <class Z>
  static double stored_energy_per_mass(const Z& z, const Material& m) {
    const double e = z[plastic_strain];
    return m.flow.stored_energy(z[equivalent_plastic_strain], 1.5 * e * e) / m.density;
  }
  template <class Z>
  static double dissipated_energy_per_mass(const Z& z) {
    return z[dissipation];
  }
};

}  // namespace dgmpm
