#pragma once
// 2D plane-strain finite strain, total Lagrangian (docs/method.md, "Finite strain"): grid and
// particles in the reference configuration X, F_t - Grad v = 0, rho0 v_t - Div P(F) = 0 with the
// nominal stress P(F) of a hyperelastic `Law` (hyperelastic_laws.hpp), F the in-plane 2 x 2 block
// (F_zz = 1). Conserved q = (F_xx, F_xy, F_yx, F_yy, rho0 v_x, rho0 v_y), F_iJ = dx_i / dX_J; the
// scheme works with specific states (F / rho0, v), as the 1D bar (finite_strain_bar.hpp).
//
// The edge's Riemann problem is linearised, each side with its own tangent: along the edge's
// normal N = e_axis, each side's edge state gives its traction t = P N and its impedance tensor
// Z = sqrt(rho0 A(N)), A_ik = dP_iJ / dF_kL N_J N_L the acoustic tensor. The star velocity and
// traction solve t* - t- = Z- (v* - v-) and t+ - t* = -Z+ (v+ - v*). The star "state" handed to
// `flux` holds (t*_x, t*_y, 0, 0, v*_x, v*_y): the flux needs nothing else (F rows -v* (x) N,
// momentum rows -t*). A boundary is a Riemann problem against a ghost with the inside's impedance
// whose velocity, traction or (roller) normal velocity and tangential traction are prescribed
// (boundary_star). A state whose acoustic tensor is not positive definite makes Z, and so the
// step, NaN; a run checks each particle's speed with its time step first, to name the particle.
//
// Corner transport (CTU): a fluctuation w = (dF, dv) entering a cell through a face normal to X
// is split into the waves of the Jacobian along the other axis Y, linearised at the cell's edge
// state on the crossed face (transverse_medium: Z_Y and the traction's tangent row
// dt_i = dP_iY / dF_kL dF_kL). Its zero-speed waves carry dF_X (with the dF_Y that keeps
// P e_Y unchanged) and no flux along Y; its moving waves carry (dt, dv) with dt = -Z dv (to +Y)
// or +Z dv (to -Y), so the part moving up is dv = (2 Z)^-1 (Z w_v - dt(w)), transmitted into the
// neighbour's medium as a Riemann problem between the two impedances. A boundary reflects it as
// its star state does a state (boundary_response).
//
// Particles carry their displacement u (internal variables, u += dt v after each step), so the
// current position is X + u.

#include "../boundary.hpp"
#include "acoustic.hpp"
#include "hyperelastic_laws.hpp"

#include <Eigen/Core>
#include <Eigen/LU>
#include <array>
#include <cmath>
#include <limits>

namespace dgmpm {

template <class Law>
struct FiniteStrainPlane {
  static constexpr int dim = 2;
  static constexpr int n_comp = 6;
  static constexpr int n_internal = 2;
  enum Internal { displacement_x = 0, displacement_y = 1 };
  static constexpr std::array<const char*, n_internal> internal_names{"displacement_x",
                                                                      "displacement_y"};
  static constexpr std::array<const char*, n_internal> internal_units{"m", "m"};
  static constexpr std::array<const char*, n_comp> state_names{"F_xx", "F_xy",       "F_yx",
                                                               "F_yy", "velocity_x", "velocity_y"};
  static constexpr std::array<const char*, n_comp> state_units{"1", "1", "1", "1", "m/s", "m/s"};
  using State = Eigen::Matrix<double, n_comp, 1>;
  using Vec = Eigen::Vector2d;
  using Mat = Eigen::Matrix2d;
  enum Component { fxx = 0, fxy = 1, fyx = 2, fyy = 3, vx = 4, vy = 5 };

  // The law's moduli and the reference density rho0; a mixed cell's by mass.
  using Material = HyperelasticMaterial;
  static Material blend(const Material& a, double ma, const Material& b, double mb) {
    return Material::blend(a, ma, b, mb);
  }
  static double density(const Material& m) { return m.density; }

  // F of a specific or physical state (row-major components).
  template <class S>
  static Mat gradient(const S& s, double scale = 1.0) {
    Mat f;
    f << s[fxx], s[fxy], s[fyx], s[fyy];
    return scale * f;
  }
  static State specific(const Mat& f, const Vec& v, const Material& m) {
    State q;
    q << f(0, 0) / m.density, f(0, 1) / m.density, f(1, 0) / m.density, f(1, 1) / m.density, v;
    return q;
  }
  static State physical(const State& q, const Material& m) {
    State s = q;
    s.template head<4>() *= m.density;
    return s;
  }

  // The longitudinal speed of the unstrained material; a run's time step uses the particles'
  // current speeds (state_wave_speed).
  static double max_wave_speed(const Material& m) {
    return std::sqrt((m.moduli.lambda + 2 * m.moduli.mu) / m.density);
  }
  // The largest speed over in-plane directions at a specific state: NaN where the acoustic tensor
  // is not positive definite in some direction.
  static double state_wave_speed(const State& q, const Material& m) {
    return dgmpm::max_wave_speed(Law::plane_tangent(gradient(q, m.density), m.moduli), m.density);
  }

  // The hyperbolic range under uniaxial strain F = diag(f, 1): f above lowest_f, the least f whose
  // acoustic tensors are positive definite in every direction (by bisection; SVK at nu = 0.3:
  // 0.70562, oblique waves failing first, above the longitudinal 1/sqrt(3)), and nominal stresses
  // P_xx above lowest_stress (a normal traction below it drives the loaded edge out of the range;
  // -infinity where no f > 0 leaves it).
  static double lowest_f(const Material& m) {
    const auto hyperbolic = [&](double f) {
      return state_wave_speed(specific(Vec(f, 1.0).asDiagonal(), Vec::Zero(), m), m) >= 0;
    };
    double lo = 1e-3, hi = 1.0;
    if (hyperbolic(lo)) return 0.0;
    while (hi - lo > 1e-12) (hyperbolic(0.5 * (lo + hi)) ? hi : lo) = 0.5 * (lo + hi);
    return hi;
  }
  static double lowest_stress(const Material& m) {
    const double f = lowest_f(m);
    return f > 0 ? Law::plane_stress(Vec(f, 1.0).asDiagonal(), m.moduli)(0, 0)
                 : -std::numeric_limits<double>::infinity();
  }

  // Specific flux along `axis`: F rows -v_i / rho0 for F_i,axis, momentum rows -P_i,axis / rho0.
  static State specific_flux(int axis, const State& q, const Material& m) {
    const Mat p = Law::plane_stress(gradient(q, m.density), m.moduli);
    const double inv = 1.0 / m.density;
    State f = State::Zero();
    f[2 * 0 + axis] = -q[vx] * inv;
    f[2 * 1 + axis] = -q[vy] * inv;
    f[vx] = -p(0, axis) * inv;
    f[vy] = -p(1, axis) * inv;
    return f;
  }

  // (t*, v*) of the linearised Riemann problem between a minus and a plus specific state.
  static State riemann(int axis, const State& qm, const Material& mm, const State& qp,
                       const Material& mp) {
    Vec tm, tp;
    Mat zm, zp;
    side_of(axis, qm, mm, tm, zm);
    side_of(axis, qp, mp, tp, zp);
    const Vec v_m = qm.template tail<2>(), v_p = qp.template tail<2>();
    const Vec v_star = (zm + zp).inverse() * (zm * v_m + zp * v_p + tp - tm);
    return star(tm + zm * (v_star - v_m), v_star);
  }
  // F_n(q*) = -(v* (x) N, t*): the same for both sides of a face.
  static State flux(int axis, const State& s, const Material&) {
    State f = State::Zero();
    f[2 * 0 + axis] = -s[vx];
    f[2 * 1 + axis] = -s[vy];
    f[vx] = -s[0];
    f[vy] = -s[1];
    return f;
  }

  // (t*, v*) of a boundary face whose inside specific state is q (side 1: the inside is the minus
  // side; side 0: the plus side), against a ghost with the inside's impedance Z: across the wave
  // into the inside, t* - t = S (v* - v) with S = Z from the minus side, -Z from the plus side.
  // Free and traction prescribe t* (value: (P_nn, P_tn), the components of P e_axis along e_axis
  // and the other axis, tension positive), velocity and fixed v* (value: (v_x, v_y)), a roller
  // v*_n = 0 and t*_t = 0 (the same as a Riemann problem against the mirror image with the
  // mirrored impedance).
  static State boundary_star(BoundaryKind kind, const Vec& value, int axis, const State& q,
                             const Material& m, int side) {
    Vec t;
    Mat s;
    side_of(axis, q, m, t, s);
    if (!side) s = -s;
    return boundary_response(kind, value, axis, t, q.template tail<2>(), s);
  }

  // --- CTU (the interface: plane_strain.hpp) -----------------------------------------------------
  // A^-dq = F(q*) - F(q-) (side 0) or A^+dq = F(q+) - F(q*) (side 1), the flux of a state being
  // -(v (x) N, P N), as a rate of the physical (F, v).
  static State fluctuation(int axis, const State& star_state, const State& q, const Material& m,
                           int side) {
    const Mat p = Law::plane_stress(gradient(q, m.density), m.moduli);
    const State own = flux(axis, star(p.col(axis), q.template tail<2>()), m);
    State w =
        side ? State(own - flux(axis, star_state, m)) : State(flux(axis, star_state, m) - own);
    w.template tail<2>() /= m.density;
    return w;
  }

  // What a transverse wave crossing a face normal to `axis` needs of the cell's edge state there:
  // the impedance tensor along the axis and the traction's tangent, dt_i = d_traction(i, 2 k + L)
  // dF_kL.
  struct Medium {
    Mat z;
    Eigen::Matrix<double, 2, 4> d_traction;
  };
  static Medium transverse_medium(int axis, const State& q, const Material& m) {
    const PlaneTangent a = Law::plane_tangent(gradient(q, m.density), m.moduli);
    Medium medium;
    for (int i = 0; i < 2; ++i)
      for (int k = 0; k < 2; ++k)
        for (int L = 0; L < 2; ++L) medium.d_traction(i, 2 * k + L) = a[i][axis][k][L];
    Mat acoustic;
    for (int i = 0; i < 2; ++i)
      for (int k = 0; k < 2; ++k) acoustic(i, k) = a[i][axis][k][axis];
    medium.z = impedance_tensor(acoustic, m.density);
    return medium;
  }

  // The part of w that leaves `here` toward +axis (up) or -axis, transmitted into `there`: a star
  // increment whose flux along the axis is B^+ w (or B^- w).
  static State transverse(int /*axis*/, const State& w, const Medium& here, const Medium& there,
                          bool up) {
    const double sign = up ? -1.0 : 1.0;  // dt = -Z dv on waves to +axis, +Z dv to -axis
    const Vec dt = here.d_traction * w.template head<4>();
    const Vec dv = (here.z + there.z).inverse() * (here.z * w.template tail<2>() + sign * dt);
    return star(sign * (there.z * dv), dv);
  }

  // Against a boundary: the wave leaving into an identical medium, and what the boundary sends
  // back, summed: the boundary's star state with no load (a velocity boundary reflects as a fixed
  // one, a traction as a free one) for that wave as the inside state.
  static State transverse_at_boundary(BoundaryKind kind, int axis, const State& w,
                                      const Medium& here, bool up) {
    const State out = transverse(axis, w, here, here, up);
    return boundary_response(kind, Vec::Zero(), axis, out.template head<2>(),
                             out.template tail<2>(), up ? here.z : Mat(-here.z));
  }

  // The MPM baseline's constitutive part, total Lagrangian (its grid is the reference
  // configuration, its particles stay at X): the nominal stress, and F += dt Grad v.
  static Mat stress_tensor(const State& q, const Material& m) {
    return Law::plane_stress(gradient(q, m.density), m.moduli);
  }
  template <class Q>
  static void add_stress_rate(Q&& q, const Mat& grad_v, const Material& m, double dt) {
    const double k = dt / m.density;
    q[fxx] += k * grad_v(0, 0);
    q[fxy] += k * grad_v(0, 1);
    q[fyx] += k * grad_v(1, 0);
    q[fyy] += k * grad_v(1, 1);
  }

  // The displacement follows the particle's velocity after the step.
  template <class Q, class Z>
  static void particle_step(Q&& q, Z&& z, const Material&, double dt) {
    z[displacement_x] += dt * q[vx];
    z[displacement_y] += dt * q[vy];
  }
  template <class Z>
  static Vec displacement_of(const Z& z) {
    return Vec(z[displacement_x], z[displacement_y]);
  }

  // Output columns derived from a particle's physical state: the nominal stress P, the Cauchy
  // stress (in-plane and sigma_zz) and J.
  static constexpr std::array<const char*, 9> derived_names{
      "nominal_stress_xx", "nominal_stress_xy", "nominal_stress_yx",
      "nominal_stress_yy", "sigma_xx",          "sigma_yy",
      "sigma_xy",          "sigma_zz",          "J"};
  static constexpr std::array<const char*, 9> derived_units{"Pa", "Pa", "Pa", "Pa", "Pa",
                                                            "Pa", "Pa", "Pa", "1"};
  template <class S, class Z>
  static std::array<double, 9> derived(const S& s, const Z&, const Material& m) {
    const Mat f = gradient(s);
    const Mat p = Law::plane_stress(f, m.moduli);
    const Eigen::Matrix3d sigma = Law::plane_cauchy(f, m.moduli);
    return {p(0, 0),     p(0, 1),     p(1, 0),     p(1, 1),        sigma(0, 0),
            sigma(1, 1), sigma(0, 1), sigma(2, 2), f.determinant()};
  }
  template <class S, class Z>
  static Eigen::Matrix3d cauchy_stress_tensor(const S& s, const Z&, const Material& m) {
    return Law::plane_cauchy(gradient(s), m.moduli);
  }
  template <class S, class Z>
  static Eigen::Matrix3d deformation_gradient_tensor(const S& s, const Z&) {
    Eigen::Matrix3d f = Eigen::Matrix3d::Identity();
    f.topLeftCorner<2, 2>() = gradient(s);
    return f;
  }

  // Energy per unit mass: kinetic |v|^2 / 2, strain W(F) / rho0.
  static double kinetic_energy_per_mass(const State& q) {
    return 0.5 * (q[vx] * q[vx] + q[vy] * q[vy]);
  }
  static double elastic_energy_per_mass(const State& q, const Material& m) {
    return Law::plane_energy(gradient(q, m.density), m.moduli) / m.density;
  }
  static double energy_per_mass(const State& q, const Material& m) {
    return kinetic_energy_per_mass(q) + elastic_energy_per_mass(q, m);
  }

 private:
  // The star state of a boundary whose inside has traction t, velocity v and, across the wave
  // into it, t* - t = S (v* - v).
  static State boundary_response(BoundaryKind kind, const Vec& value, int axis, const Vec& t,
                                 const Vec& v, const Mat& s) {
    const int n = axis, tg = 1 - axis;
    switch (kind) {
      case BoundaryKind::free:
        return star(Vec::Zero(), v - s.inverse() * t);
      case BoundaryKind::traction: {
        Vec prescribed;
        prescribed[n] = value[0];
        prescribed[tg] = value[1];
        return star(prescribed, v + s.inverse() * (prescribed - t));
      }
      case BoundaryKind::fixed:
        return star(t - s * v, Vec::Zero());
      case BoundaryKind::velocity:
        return star(t + s * (value - v), value);
      case BoundaryKind::roller: {
        Vec v_star;
        v_star[n] = 0.0;
        v_star[tg] = v[tg] + (s(tg, n) * v[n] - t[tg]) / s(tg, tg);
        return star(t + s * (v_star - v), v_star);
      }
    }
    return star(t, v);
  }
  static State star(const Vec& t, const Vec& v) {
    State s;
    s << t, 0.0, 0.0, v;
    return s;
  }
  // A side's traction P e_axis and impedance tensor along e_axis, from its specific state.
  static void side_of(int axis, const State& q, const Material& m, Vec& t, Mat& z) {
    const PlaneEdge e = Law::plane_edge(gradient(q, m.density), axis, m.moduli);
    t = e.traction;
    z = impedance_tensor(e.acoustic, m.density);
  }
};

}  // namespace dgmpm
