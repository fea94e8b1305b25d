#pragma once
// 1D finite strain, total Lagrangian, uniaxial strain (docs/method.md, "Finite strain"): grid and
// particles in the reference configuration X, F_t - v_X = 0, rho0 v_t - P(F)_X = 0 with the
// nominal stress P(F) of a hyperelastic `Law` (hyperelastic_laws.hpp). Conserved q = (F, rho0 v);
// the scheme works with specific states q^s = (F / rho0, v), as the elastic bar with sigma.
//
// The edge's Riemann problem is linearised, each side with its own tangent: impedances
// Z = sqrt(rho0 dP/dF(F)) of the sides' edge states give the star velocity and nominal stress
// (v*, P*) as for small strain; the star state handed to `flux` is (P*, v*), not a state of F
// (F* is never needed: the flux is -(v*, P*)). A boundary is a Riemann problem against a ghost
// with the interior's impedance whose velocity or traction is prescribed (boundary_star): no
// ghost F reproduces a prescribed traction, since Z changes with F. A tangent that is not
// positive (SVK in compression past F = 1/sqrt(3)) makes Z, and so the step, NaN: the operator's
// finiteness check stops there; a run checks each particle's tangent with its time step
// (state_wave_speed) first, to name the particle.
//
// Particles carry their displacement u (an internal variable, u += dt v after each step, as
// moving particles are advanced), so the current position is X + u.

#include "../boundary.hpp"
#include "hyperelastic_laws.hpp"

#include <Eigen/Core>
#include <array>
#include <cmath>
#include <limits>

namespace dgmpm {

// The default safety factor of an automatic step with finite strain (time.safety): the linear
// analysis' admissible Courant number holds for the linearised operator, but a step at it gains
// energy at shocks and fans (the state behind moves faster than the speeds the step was chosen
// with: +0.9% of the work at an SVK 2 GPa shock, +9% at 20 GPa and +7% in the -20 GPa fan with
// RK2, at Courant 1); at 0.9 times it every test scene loses energy (docs/method.md).
inline constexpr double kFiniteStrainSafety = 0.9;

template <class Law>
struct FiniteStrainBar {
  static constexpr int dim = 1;
  static constexpr int n_comp = 2;
  static constexpr int n_internal = 1;
  enum Internal { displacement = 0 };
  static constexpr std::array<const char*, n_internal> internal_names{"displacement"};
  static constexpr std::array<const char*, n_internal> internal_units{"m"};
  // The physical state's components (F, v), as output columns, and their SI units.
  static constexpr std::array<const char*, n_comp> state_names{"F", "velocity"};
  static constexpr std::array<const char*, n_comp> state_units{"1", "m/s"};
  using State = Eigen::Matrix<double, n_comp, 1>;
  enum Component { deformation_gradient = 0, velocity = 1 };

  // The law's moduli and the reference density rho0; a mixed cell's by mass.
  using Material = HyperelasticMaterial;
  static Material blend(const Material& a, double ma, const Material& b, double mb) {
    return Material::blend(a, ma, b, mb);
  }

  // The law at a deformation gradient F.
  static double nominal_stress(double f, const Material& m) {
    return Law::uniaxial_stress(f, m.moduli);
  }
  static double tangent(double f, const Material& m) { return Law::uniaxial_tangent(f, m.moduli); }
  static double strain_energy(double f, const Material& m) {
    return Law::uniaxial_energy(f, m.moduli);
  }
  // The longitudinal wave speed at F: sqrt(dP/dF / rho0) (NaN where the tangent is negative).
  static double wave_speed(double f, const Material& m) {
    return std::sqrt(tangent(f, m) / m.density);
  }
  // The speed in the unstrained material (F = 1): a run's time step must use the particles'
  // current speeds (wave_speed), which grow in tension.
  static double max_wave_speed(const Material& m) { return wave_speed(1.0, m); }
  // The speed at a particle's specific state (NaN outside the hyperbolic range).
  static double state_wave_speed(const State& q, const Material& m) {
    return wave_speed(q[0] * m.density, m);
  }
  // The hyperbolic range is F > lowest_f; the nominal stresses it reaches are above
  // lowest_stress (SVK: P(1/sqrt(3)) = -M / (3 sqrt(3)); neo-Hookean: every stress).
  static double lowest_f(const Material&) { return Law::uniaxial_lowest_f(); }
  static double lowest_stress(const Material& m) {
    const double f = Law::uniaxial_lowest_f();
    return f > 0 ? nominal_stress(f, m) : -std::numeric_limits<double>::infinity();
  }
  static double density(const Material& m) { return m.density; }

  static State specific(double f, double v, const Material& m) { return {f / m.density, v}; }
  // Physical state (F, v) of a specific state.
  static State physical(const State& q, const Material& m) { return {q[0] * m.density, q[1]}; }

  // Specific flux F^s = F / rho0 along the axis: -(v, P(F)) / rho0.
  static State specific_flux(int /*axis*/, const State& q, const Material& m) {
    return {-q[1] / m.density, -nominal_stress(q[0] * m.density, m) / m.density};
  }

  // (P*, v*) of the linearised Riemann problem between a minus and a plus specific state.
  static State riemann(int /*axis*/, const State& qm, const Material& mm, const State& qp,
                       const Material& mp) {
    const double fm = qm[0] * mm.density, fp = qp[0] * mp.density;
    const double zm = impedance(fm, mm), zp = impedance(fp, mp);
    const double pm = nominal_stress(fm, mm), pp = nominal_stress(fp, mp);
    const double v_star = (zm * qm[1] + zp * qp[1] + pp - pm) / (zm + zp);
    return {pm + zm * (v_star - qm[1]), v_star};
  }
  // F_n(q*) = -(v*, P*): the same for both sides of a face.
  static State flux(int /*axis*/, const State& star, const Material&) {
    return {-star[1], -star[0]};
  }

  // (P*, v*) of a boundary face whose inside specific state is q (side 1: the inside is the minus
  // side, the face its upper one; side 0: the plus side), against a ghost with the inside's
  // impedance: traction and free prescribe P* (value: P_11, tension positive), velocity and fixed
  // v*; a roller is fixed in 1D.
  static State boundary_star(BoundaryKind kind, const Eigen::Matrix<double, 1, 1>& value,
                             int /*axis*/, const State& q, const Material& m, int side) {
    const double f = q[0] * m.density, v = q[1];
    const double z = impedance(f, m), p = nominal_stress(f, m);
    // Across the wave into the inside: P* - P = z (v* - v) from the minus side, -z from the plus.
    const double s = side ? z : -z;
    switch (kind) {
      case BoundaryKind::free:
        return {0.0, v - p / s};
      case BoundaryKind::traction:
        return {value[0], v + (value[0] - p) / s};
      case BoundaryKind::fixed:
      case BoundaryKind::roller:
        return {p - s * v, 0.0};
      case BoundaryKind::velocity:
        return {p + s * (value[0] - v), value[0]};
    }
    return {p, v};
  }

  // The MPM baseline's constitutive part, total Lagrangian as this physics (its grid is the
  // reference configuration, its particles stay at X): the nominal stress the internal force
  // integrates over the reference volume, and F += dt dv/dX in specific form.
  static Eigen::Matrix<double, 1, 1> stress_tensor(const State& q, const Material& m) {
    return Eigen::Matrix<double, 1, 1>(nominal_stress(q[0] * m.density, m));
  }
  template <class Q>
  static void add_stress_rate(Q&& q, const Eigen::Matrix<double, 1, 1>& grad_v, const Material& m,
                              double dt) {
    q[0] += dt * grad_v(0, 0) / m.density;
  }

  // The displacement follows the particle's velocity after the step.
  template <class Q, class Z>
  static void particle_step(Q&& q, Z&& z, const Material&, double dt) {
    z[displacement] += dt * q[velocity];
  }
  template <class Z>
  static Eigen::Matrix<double, 1, 1> displacement_of(const Z& z) {
    return Eigen::Matrix<double, 1, 1>(z[displacement]);
  }

  // Output columns derived from a particle's physical state (F, v): the nominal stress P_xx, the
  // lateral Cauchy stress sigma_yy = sigma_zz (sigma_xx = P_xx in uniaxial strain) and J = F.
  static constexpr std::array<const char*, 3> derived_names{"nominal_stress", "sigma_yy", "J"};
  static constexpr std::array<const char*, 3> derived_units{"Pa", "Pa", "1"};
  template <class S, class Z>
  static std::array<double, 3> derived(const S& s, const Z&, const Material& m) {
    return {nominal_stress(s[0], m), Law::uniaxial_lateral_stress(s[0], m.moduli), s[0]};
  }
  // The Cauchy stress diag(P, sigma_yy, sigma_yy) and F = diag(F, 1, 1), 3 x 3, for outputs.
  template <class S, class Z>
  static Eigen::Matrix3d cauchy_stress_tensor(const S& s, const Z&, const Material& m) {
    const double lateral = Law::uniaxial_lateral_stress(s[0], m.moduli);
    return Eigen::Vector3d(nominal_stress(s[0], m), lateral, lateral).asDiagonal();
  }
  template <class S, class Z>
  static Eigen::Matrix3d deformation_gradient_tensor(const S& s, const Z&) {
    return Eigen::Vector3d(s[0], 1.0, 1.0).asDiagonal();
  }

  // Energy per unit mass: kinetic v^2 / 2, strain W(F) / rho0.
  static double kinetic_energy_per_mass(const State& q) { return 0.5 * q[1] * q[1]; }
  static double elastic_energy_per_mass(const State& q, const Material& m) {
    return strain_energy(q[0] * m.density, m) / m.density;
  }
  static double energy_per_mass(const State& q, const Material& m) {
    return kinetic_energy_per_mass(q) + elastic_energy_per_mass(q, m);
  }

 private:
  static double impedance(double f, const Material& m) {
    return std::sqrt(m.density * tangent(f, m));
  }
};

}  // namespace dgmpm
