#pragma once
// 1D linear elastic bar (docs/method.md, "Equations"): q = (sigma, rho v), F(q) = -(E v, sigma).
// The scheme works with specific states q^s = (sigma / rho, v).

#include "../boundary.hpp"

#include <Eigen/Core>
#include <array>
#include <cmath>

namespace dgmpm {

struct ElasticBar {
  static constexpr int dim = 1;
  static constexpr int n_comp = 2;
  static constexpr int n_internal = 0;  // no internal variables (elastic)
  static constexpr std::array<const char*, n_internal> internal_names{};  // output columns
  static constexpr std::array<const char*, n_internal> internal_units{};  // SI
  // The physical state's components (sigma, v), as output columns, and their SI units.
  static constexpr std::array<const char*, n_comp> state_names{"stress", "velocity"};
  static constexpr std::array<const char*, n_comp> state_units{"Pa", "m/s"};
  using State = Eigen::Matrix<double, n_comp, 1>;
  enum Component { stress = 0, velocity = 1 };

  // Immutable once built: the wave speed, impedance and E / rho are computed once, not at every
  // face or node (a division in the volume term costs more than the rest of it).
  class Material {
   public:
    Material() : Material(1.0, 1.0) {}
    Material(double young, double density)
        : young(young), density(density), c_(std::sqrt(young / density)),
          z_(std::sqrt(young * density)), specific_modulus_(young / density),
          inverse_double_z_(1.0 / (z_ + z_)) {}
    double young, density;
    double wave_speed() const { return c_; }
    double impedance() const { return z_; }
    double specific_modulus() const { return specific_modulus_; }  // E / rho
    // 1 / (2 Z): the Riemann solve's factor between two cells of this material.
    double inverse_double_impedance() const { return inverse_double_z_; }

   private:
    double c_, z_, specific_modulus_, inverse_double_z_;
  };

  // The material of a cell holding particles of several materials (ma of a, mb of b): the density
  // of their mass over their volume, and rho / E, the weight of the specific stress in the energy
  // per unit mass, their mass-weighted mean. The cell's energy then counts each particle's
  // compliance: for equal densities 1 / E is the volume-weighted mean (Reuss, the uniaxial-stress
  // mixture). (A mass-weighted mean of E makes a soft particle beside stiff ones take the stiff
  // stress rate: its energy sigma^2 / 2E then grows without bound.)
  static Material blend(const Material& a, double ma, const Material& b, double mb) {
    const double w = mb / (ma + mb);
    const double density = (ma + mb) / (ma / a.density + mb / b.density);
    const double compliance = (1 - w) * a.density / a.young + w * b.density / b.young;  // rho / E
    return {density / compliance, density};
  }

  static double max_wave_speed(const Material& m) { return m.wave_speed(); }
  static double density(const Material& m) { return m.density; }

  static State specific(double sigma, double v, const Material& m) {
    return {sigma / m.density, v};
  }

  // Specific flux F^s = F / rho along the axis, linear in q (physics::LinearFlux).
  static constexpr bool linear_flux = true;
  static State specific_flux(int /*axis*/, const State& q, const Material& m) {
    return {-m.specific_modulus() * q[1], -q[0]};
  }

  static State physical(const State& q, const Material& m) { return {q[0] * m.density, q[1]}; }

  // Star state (sigma*, v*) of the Riemann problem between a minus and a plus state.
  static State riemann(int /*axis*/, const State& qm, const Material& mm, const State& qp,
                       const Material& mp) {
    const double zm = mm.impedance(), zp = mp.impedance();
    const double sm = qm[0] * mm.density, sp = qp[0] * mp.density;
    // One material on both sides (the same table entry): its factor, not a division per face.
    const double inv = &mm == &mp ? mm.inverse_double_impedance() : 1.0 / (zm + zp);
    const double v_star = (zm * qm[1] + zp * qp[1] + sp - sm) * inv;
    const double s_star = (zp * sm + zm * sp + zm * zp * (qp[1] - qm[1])) * inv;
    return {s_star, v_star};
  }
  // F(q*) with m's modulus: each side of a face its own (the strain flux -v* is shared).
  static State flux(int /*axis*/, const State& star, const Material& m) {
    return {-m.young * star[1], -star[0]};
  }

  // Ghost state outside a face whose inside state is q (value: the prescribed sigma or v).
  static State ghost(BoundaryKind kind, const Eigen::Matrix<double, 1, 1>& value, int /*axis*/,
                     const State& q, const Material& m) {
    const double sigma = q[0] * m.density, v = q[1];
    switch (kind) {
      case BoundaryKind::free:
        return specific(-sigma, v, m);
      case BoundaryKind::fixed:
      case BoundaryKind::roller:  // v_n = 0 is all a roller says in 1D
        return specific(sigma, -v, m);
      case BoundaryKind::traction:
        return specific(2.0 * value[0] - sigma, v, m);
      case BoundaryKind::velocity:
        return specific(sigma, 2.0 * value[0] - v, m);
    }
    return q;
  }

  // MPM's constitutive part: the stress of a state, and sigma += dt E dv/dx in specific form.
  static Eigen::Matrix<double, 1, 1> stress_tensor(const State& q, const Material& m) {
    return Eigen::Matrix<double, 1, 1>(m.density * q[0]);
  }
  template <class Q>
  static void add_stress_rate(Q&& q, const Eigen::Matrix<double, 1, 1>& grad_v, const Material& m,
                              double dt) {
    q[0] += dt * m.specific_modulus() * grad_v(0, 0);
  }

  // The strain of a physical state (sigma, v) for outputs: the bar's axial strain sigma / E (its
  // lateral strains are not modelled) as a 3 x 3 tensor.
  template <class Z>
  static Eigen::Matrix3d strain_tensor(const State& s, const Z&, const Material& m) {
    Eigen::Matrix3d e = Eigen::Matrix3d::Zero();
    e(0, 0) = s[stress] / m.young;
    return e;
  }

  // Energy per unit mass: kinetic v^2 / 2, elastic sigma^2 / (2 E rho) = s^2 rho / (2 E).
  static double kinetic_energy_per_mass(const State& q) { return 0.5 * q[1] * q[1]; }
  static double elastic_energy_per_mass(const State& q, const Material& m) {
    return 0.5 * q[0] * q[0] * (m.density / m.young);
  }
  static double energy_per_mass(const State& q, const Material& m) {
    return kinetic_energy_per_mass(q) + elastic_energy_per_mass(q, m);
  }
};

}  // namespace dgmpm
