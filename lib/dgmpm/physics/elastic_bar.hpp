#pragma once
// 1D linear elastic bar (method.md 1): q = (sigma, rho v), F(q) = -(E v, sigma). The scheme works
// with specific states q^s = (sigma / rho, v).

#include "../boundary.hpp"

#include <Eigen/Core>
#include <cmath>

namespace dgmpm {

struct ElasticBar {
  static constexpr int dim = 1;
  static constexpr int n_comp = 2;
  using State = Eigen::Matrix<double, n_comp, 1>;
  enum Component { stress = 0, velocity = 1 };

  // Immutable once built: the wave speed and impedance are computed once, not at every face.
  class Material {
   public:
    Material() : Material(1.0, 1.0) {}
    Material(double young, double density)
        : young(young), density(density), c_(std::sqrt(young / density)),
          z_(std::sqrt(young * density)) {}
    double young, density;
    double wave_speed() const { return c_; }
    double impedance() const { return z_; }

   private:
    double c_, z_;
  };

  // Mass-weighted blend, for cells holding particles of several materials.
  static Material blend(const Material& a, double ma, const Material& b, double mb) {
    const double w = mb / (ma + mb);
    return {(1 - w) * a.young + w * b.young, (1 - w) * a.density + w * b.density};
  }

  static double max_wave_speed(const Material& m) { return m.wave_speed(); }
  static double density(const Material& m) { return m.density; }

  static State specific(double sigma, double v, const Material& m) {
    return {sigma / m.density, v};
  }
  static double stress_of(const State& q, double density) { return q[0] * density; }
  static double velocity_of(const State& q) { return q[1]; }

  // Specific flux F^s = F / rho along the axis.
  static State specific_flux(int /*axis*/, const State& q, const Material& m) {
    return {-(m.young / m.density) * q[1], -q[0]};
  }

  // Godunov flux through a face between a minus and a plus state: the star state of the
  // Riemann problem, then F(q*) with each side's own modulus (the strain flux -v* is shared).
  static void godunov(int /*axis*/, const State& qm, const Material& mm, const State& qp,
                      const Material& mp, State& flux_m, State& flux_p) {
    const double zm = mm.impedance(), zp = mp.impedance();
    const double sm = qm[0] * mm.density, sp = qp[0] * mp.density;
    const double inv = 1.0 / (zm + zp);
    const double v_star = (zm * qm[1] + zp * qp[1] + sp - sm) * inv;
    const double s_star = (zp * sm + zm * sp + zm * zp * (qp[1] - qm[1])) * inv;
    flux_m = {-mm.young * v_star, -s_star};
    flux_p = {-mp.young * v_star, -s_star};
  }

  // Ghost state outside a face whose inside state is q.
  static State ghost(const BoundaryCondition<1>& bc, double t, const State& q, const Material& m) {
    const double sigma = q[0] * m.density, v = q[1];
    switch (bc.kind) {
      case BoundaryKind::free:
        return specific(-sigma, v, m);
      case BoundaryKind::fixed:
        return specific(sigma, -v, m);
      case BoundaryKind::traction:
        return specific(2.0 * bc.value(t)[0] - sigma, v, m);
      case BoundaryKind::velocity:
        return specific(sigma, 2.0 * bc.value(t)[0] - v, m);
    }
    return q;
  }
  // A void neighbour cell is a free surface.
  static State void_ghost(const State& q, const Material& m) {
    return specific(-q[0] * m.density, q[1], m);
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
