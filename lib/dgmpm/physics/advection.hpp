#pragma once
// Scalar advection u_t + a . grad u = 0: the model of the von Neumann analysis (docs/method.md,
// "Stability"). Density plays no role: the specific state is u itself.

#include "../boundary.hpp"

#include <Eigen/Core>
#include <array>
#include <cmath>

namespace dgmpm {

template <int Dim>
struct Advection {
  static constexpr int dim = Dim;
  static constexpr int n_comp = 1;
  static constexpr int n_internal = 0;  // no internal variables (elastic)
  static constexpr std::array<const char*, n_internal> internal_names{};  // output columns
  static constexpr std::array<const char*, n_internal> internal_units{};  // SI
  static constexpr std::array<const char*, n_comp> state_names{"u"};
  static constexpr std::array<const char*, n_comp> state_units{"1"};
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
  static State physical(const State& q, const Material&) { return q; }
  // Upwind value (the speed averaged over the two sides decides the direction).
  static State riemann(int axis, const State& qm, const Material& mm, const State& qp,
                       const Material& mp) {
    return 0.5 * (mm.speed[axis] + mp.speed[axis]) >= 0.0 ? qm : qp;
  }
  static State flux(int axis, const State& star, const Material& m) {
    return State(m.speed[axis] * star[0]);
  }
  // Inflow value for traction/velocity kinds, zero for fixed and roller, outflow (copy) for free.
  static State ghost(BoundaryKind kind, const Eigen::Matrix<double, Dim, 1>& value, int /*axis*/,
                     const State& q, const Material&) {
    switch (kind) {
      case BoundaryKind::free:
        return q;
      case BoundaryKind::fixed:
      case BoundaryKind::roller:
        return State::Zero();
      default:
        return State(value[0]);
    }
  }
  // CTU (see PlaneStrain for the interface).
  static State fluctuation(int axis, const State& star, const State& q, const Material& m,
                           int side) {
    return side ? State(flux(axis, q, m) - flux(axis, star, m))
                : State(flux(axis, star, m) - flux(axis, q, m));
  }
  static State transverse(int axis, const State& w, const Material& here, const Material& there,
                          bool up) {
    const double b = 0.5 * (here.speed[axis] + there.speed[axis]);
    return (up ? b > 0.0 : b < 0.0) ? w : State::Zero();
  }
  static State transverse_at_boundary(BoundaryKind kind, int axis, const State& w,
                                      const Material& m, bool up) {
    return transverse(axis, w, m, m, up) + transverse(axis, reflect(kind, axis, w), m, m, !up);
  }
  static State reflect(BoundaryKind kind, int /*axis*/, const State& w) {
    return kind == BoundaryKind::free ? w : State::Zero();
  }
  static double energy_per_mass(const State& q, const Material&) { return 0.5 * q[0] * q[0]; }
};

}  // namespace dgmpm
