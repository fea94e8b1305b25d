#pragma once
// Scalar advection u_t + a . grad u = 0: the model of the von Neumann analysis (method.md 5).
// Density plays no role: the specific state is u itself.

#include "../boundary.hpp"

#include <Eigen/Core>
#include <cmath>

namespace dgmpm {

template <int Dim>
struct Advection {
  static constexpr int dim = Dim;
  static constexpr int n_comp = 1;
  using State = Eigen::Matrix<double, 1, 1>;

  struct Material {
    Eigen::Matrix<double, Dim, 1> speed = Eigen::Matrix<double, Dim, 1>::Ones();
  };
  static Material blend(const Material& a, double ma, const Material& b, double mb) {
    return {(ma * a.speed + mb * b.speed) / (ma + mb)};
  }
  static double max_wave_speed(const Material& m) { return m.speed.cwiseAbs().maxCoeff(); }
  // Mass per unit volume of a full cell: advected particles carry their volume as mass.
  static double density(const Material&) { return 1.0; }

  static State specific_flux(int axis, const State& q, const Material& m) {
    return State(m.speed[axis] * q[0]);
  }
  // Upwind flux; both sides see the same flux.
  static void godunov(int axis, const State& qm, const Material& mm, const State& qp,
                      const Material& mp, State& flux_m, State& flux_p) {
    const double a = 0.5 * (mm.speed[axis] + mp.speed[axis]);
    flux_m = flux_p = State(a >= 0.0 ? a * qm[0] : a * qp[0]);
  }
  // Inflow value for traction/velocity kinds, zero for fixed, outflow (copy) for free.
  static State ghost(const BoundaryCondition<Dim>& bc, double t, const State& q, const Material&) {
    switch (bc.kind) {
      case BoundaryKind::free:
        return q;
      case BoundaryKind::fixed:
        return State::Zero();
      default:
        return State(bc.value(t)[0]);
    }
  }
  static State void_ghost(const State& q, const Material&) { return q; }
  static double energy_per_mass(const State& q, const Material&) { return 0.5 * q[0] * q[0]; }
};

}  // namespace dgmpm
