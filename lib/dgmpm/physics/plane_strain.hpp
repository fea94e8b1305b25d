#pragma once
// 2D plane-strain linear elasticity (docs/method.md, "Equations"). Conservative state
// q = (sigma_xx, sigma_yy, sigma_xy, rho v_x, rho v_y); the scheme works with the specific state
// q^s = (sigma / rho, v). sigma_zz = nu (sigma_xx + sigma_yy) is derived, never evolved.
//
// The interface of a physics (shared with ElasticBar and Advection, used by DGOperator):
//   riemann(axis, q-, m-, q+, m+)   star state of the edge's Riemann problem, physical (sigma, v)
//   flux(axis, star, m)             F_n(q*) with m's moduli (each side of an edge uses its own)
//   specific_flux(axis, q, m)       F_n(q) / rho, the volume term's flux
//   ghost(kind, value, axis, q, m)  outside state that makes the boundary Riemann problem return
//                                   the prescribed value
// and, for CTU only:
//   fluctuation(axis, star, q, m, side)  A^-dq (side 0, into the minus cell) or A^+dq (side 1)
//                                        as a rate of the physical state (sigma, v)
//   transverse(axis, w, here, there, up) the part of w that a transverse wave carries from `here`
//                                        across the edge normal to `axis` into `there` (up: to
//                                        +axis), as a star-state increment: F_axis of it is B^+w
//                                        (or B^-w)
//   transverse_at_boundary(kind, axis, w, m, up)
//                                        the same against a boundary normal to `axis`: the
//                                        outgoing wave and its reflection (the mirror image's
//                                        wave coming back in; reflect: the mirror map R, the
//                                        linear part of the ghost)

#include "../boundary.hpp"
#include "small_strain.hpp"

#include <Eigen/Core>
#include <array>
#include <cmath>

namespace dgmpm {

struct PlaneStrain {
  static constexpr int dim = 2;
  static constexpr int n_comp = 5;
  static constexpr int n_internal = 0;  // no internal variables (elastic)
  static constexpr std::array<const char*, n_internal> internal_names{};  // output columns
  static constexpr std::array<const char*, n_internal> internal_units{};  // SI
  // The physical state's components (sigma, v), as output columns, and their SI units.
  static constexpr std::array<const char*, n_comp> state_names{"sigma_xx", "sigma_yy", "sigma_xy",
                                                               "velocity_x", "velocity_y"};
  static constexpr std::array<const char*, n_comp> state_units{"Pa", "Pa", "Pa", "m/s", "m/s"};
  using State = Eigen::Matrix<double, n_comp, 1>;
  using Vec = Eigen::Matrix<double, 2, 1>;
  enum Component { sxx = 0, syy = 1, sxy = 2, vx = 3, vy = 4 };

  // Index of sigma_nn for a normal along `axis`, of sigma_tt, and of v_n, v_t.
  static constexpr int normal_stress(int axis) { return axis == 0 ? sxx : syy; }
  static constexpr int tangential_stress(int axis) { return axis == 0 ? syy : sxx; }
  static constexpr int normal_velocity(int axis) { return vx + axis; }
  static constexpr int tangential_velocity(int axis) { return vx + 1 - axis; }
  // The state of components (sigma_nn, sigma_tt, sigma_nt, v_n, v_t) along `axis`, from its five
  // values in one expression rather than by stores at indices computed from the axis, which the
  // step's packet reads then waited for (store forwarding failing): 2D DCU Euler 0.92x the time.
  static State along(int axis, double nn, double tt, double nt, double vn, double vt) {
    return axis == 0 ? State(nn, tt, nt, vn, vt) : State(tt, nn, nt, vt, vn);
  }

  // Immutable once built: wave speeds, impedances and 1 / rho are computed once, not at every
  // edge or node (a division in the volume term costs more than the rest of it).
  class Material {
   public:
    Material() : Material(1.0, 0.0, 1.0) {}
    Material(double young, double poisson, double density)
        : young(young), poisson(poisson), density(density),
          lambda_(young * poisson / ((1 + poisson) * (1 - 2 * poisson))),
          mu_(young / (2 * (1 + poisson))) {
      finish();
    }
    static Material from_lame(double lambda, double mu, double density) {
      Material m;
      m.lambda_ = lambda;
      m.mu_ = mu;
      m.density = density;
      m.young = mu * (3 * lambda + 2 * mu) / (lambda + mu);
      m.poisson = lambda / (2 * (lambda + mu));
      m.finish();
      return m;
    }
    double young, poisson, density;
    double lambda() const { return lambda_; }
    double mu() const { return mu_; }
    double p_modulus() const { return lambda_ + 2 * mu_; }
    double p_speed() const { return cp_; }
    double s_speed() const { return cs_; }
    double p_impedance() const { return zp_; }
    double s_impedance() const { return zs_; }
    double inverse_density() const { return inverse_density_; }
    double lambda_over_p_speed() const { return lambda_over_cp_; }  // CTU's transverse waves
    // 1 / (2 Z): the Riemann solve's factor between two cells of this material.
    double inverse_double_p_impedance() const { return inverse_double_zp_; }
    double inverse_double_s_impedance() const { return inverse_double_zs_; }

   private:
    void finish() {
      cp_ = std::sqrt(p_modulus() / density);
      cs_ = std::sqrt(mu_ / density);
      zp_ = density * cp_;
      zs_ = density * cs_;
      inverse_density_ = 1.0 / density;
      lambda_over_cp_ = lambda_ / cp_;
      inverse_double_zp_ = 1.0 / (zp_ + zp_);
      inverse_double_zs_ = 1.0 / (zs_ + zs_);
    }
    double lambda_ = 0, mu_ = 0.5, cp_ = 1, cs_ = 1, zp_ = 1, zs_ = 1, inverse_density_ = 1,
           lambda_over_cp_ = 0, inverse_double_zp_ = 0.5, inverse_double_zs_ = 0.5;
  };

  // The material of a cell holding particles of several materials (ma of a, mb of b), as for the
  // bar (elastic_bar.hpp): the density of their mass over their volume, and the in-plane
  // compliance times rho (the weights of the specific stresses in the energy per unit mass) their
  // mass-weighted mean. Plane-strain compliances [[s, t], [t, s]] (normal stresses) and 1 / mu
  // (shear) with s - t = 1 / (2 mu) stay of that isotropic form when averaged.
  static Material blend(const Material& a, double ma, const Material& b, double mb) {
    const double w = mb / (ma + mb);
    const double density = (ma + mb) / (ma / a.density + mb / b.density);
    // rho s and rho t of each material: the inverse of [[lambda + 2 mu, lambda], [lambda, ...]].
    const auto weighted = [](const Material& m) {
      const double p = m.p_modulus(), l = m.lambda(), det = (p - l) * (p + l);
      return Eigen::Vector2d(m.density * p / det, -m.density * l / det);
    };
    const Eigen::Vector2d st = ((1 - w) * weighted(a) + w * weighted(b)) / density;
    const double det = (st[0] - st[1]) * (st[0] + st[1]);
    return Material::from_lame(-st[1] / det, 0.5 / (st[0] - st[1]), density);
  }
  static double max_wave_speed(const Material& m) { return m.p_speed(); }
  static double density(const Material& m) { return m.density; }

  // sigma = (sigma_xx, sigma_yy, sigma_xy), v = (v_x, v_y).
  static State specific(const Eigen::Vector3d& sigma, const Vec& v, const Material& m) {
    State q;
    q << sigma / m.density, v;
    return q;
  }
  // Physical state (sigma, v) of a specific state.
  static State physical(const State& q, const Material& m) {
    State s = q;
    s.head<3>() *= m.density;
    return s;
  }
  static double sigma_zz(const State& physical_state, const Material& m) {
    return m.poisson * (physical_state[sxx] + physical_state[syy]);
  }
  // The same with a particle's internal variables (none here; plastic flow changes it).
  template <class Z>
  static double sigma_zz(const State& physical_state, const Material& m, const Z&) {
    return sigma_zz(physical_state, m);
  }

  // F^s = F / rho along `axis`, linear in q (physics::LinearFlux).
  static constexpr bool linear_flux = true;
  static State specific_flux(int axis, const State& q, const Material& m) {
    const double vn = q[normal_velocity(axis)], vt = q[tangential_velocity(axis)];
    const double inv = m.inverse_density();
    return along(axis, -m.p_modulus() * inv * vn, -m.lambda() * inv * vn, -m.mu() * inv * vt,
                 -q[normal_stress(axis)], -q[sxy]);
  }

  // F_n of a physical state s with m's moduli: stress rows -C : sym(v (x) n), momentum rows -t.
  static State flux(int axis, const State& s, const Material& m) {
    const double vn = s[normal_velocity(axis)], vt = s[tangential_velocity(axis)];
    return along(axis, -m.p_modulus() * vn, -m.lambda() * vn, -m.mu() * vt, -s[normal_stress(axis)],
                 -s[sxy]);
  }

  // One 1D Riemann problem per pair: (v_n, sigma_nn) at c_p, (v_t, sigma_nt) at c_s, each with
  // its own impedance on each side. Only the components that F_n reads are set.
  static State riemann(int axis, const State& qm, const Material& mm, const State& qp,
                       const Material& mp) {
    const int nn = normal_stress(axis), vn = normal_velocity(axis), vt = tangential_velocity(axis);
    // One material on both sides (the same table entry): its factors, not a division per face.
    const bool same = &mm == &mp;
    const double zpm = mm.p_impedance(), zpp = mp.p_impedance();
    const double zsm = mm.s_impedance(), zsp = mp.s_impedance();
    double s_nn, v_n, s_nt, v_t;
    pair_star(zpm, qm[nn] * mm.density, qm[vn], zpp, qp[nn] * mp.density, qp[vn],
              same ? mm.inverse_double_p_impedance() : 1.0 / (zpm + zpp), s_nn, v_n);
    pair_star(zsm, qm[sxy] * mm.density, qm[vt], zsp, qp[sxy] * mp.density, qp[vt],
              same ? mm.inverse_double_s_impedance() : 1.0 / (zsm + zsp), s_nt, v_t);
    return along(axis, s_nn, 0.0, s_nt, v_n, v_t);
  }

  // Ghost state (specific) outside an edge normal to `axis` whose inside state is q: the mirror
  // image R q (reflect, below) plus twice the prescribed data. Traction value: (sigma_nn,
  // sigma_nt) prescribed; velocity value: (v_x, v_y).
  static State ghost(BoundaryKind kind, const Vec& value, int axis, const State& q,
                     const Material& m) {
    State g = reflect(kind, axis, q);
    if (kind == BoundaryKind::traction) {
      g[normal_stress(axis)] += 2.0 * value[0] / m.density;
      g[sxy] += 2.0 * value[1] / m.density;
    } else if (kind == BoundaryKind::velocity) {
      g[vx] += 2.0 * value[0];
      g[vy] += 2.0 * value[1];
    }
    return g;
  }

  // --- CTU -----------------------------------------------------------------------------------
  // A^-dq = F(q*) - F(q-) (side 0) or A^+dq = F(q+) - F(q*) (side 1) with the entered cell's
  // moduli, momentum rows turned into velocity rates with its density. F is linear: one flux of
  // the difference.
  static State fluctuation(int axis, const State& star, const State& q, const Material& m,
                           int side) {
    const State jump = side ? State(physical(q, m) - star) : State(star - physical(q, m));
    State w = flux(axis, jump, m);
    w.tail<2>() *= m.inverse_density();
    return w;
  }

  // Transverse waves along `axis` (P: v_n with sigma_nn, S: v_t with sigma_nt): the part of the
  // fluctuation w (a rate of (sigma, v) in `here`) that leaves `here` toward +axis (up) or -axis
  // across the edge between `here` and `there`, split at that edge as in a Riemann problem
  // between the two materials, and carried by `there`'s eigenvector.
  static State transverse(int axis, const State& w, const Material& here, const Material& there,
                          bool up) {
    const int nn = normal_stress(axis), tt = tangential_stress(axis);
    const int vn = normal_velocity(axis), vt = tangential_velocity(axis);
    const double zph = here.p_impedance(), zpt = there.p_impedance();
    const double zsh = here.s_impedance(), zst = there.s_impedance();
    const double sign = up ? -1.0 : 1.0;  // sigma = -Z v on waves to +axis, +Z v to -axis
    const double bp = (zph * w[vn] + sign * w[nn]) / (zph + zpt);
    const double bs = (zsh * w[vt] + sign * w[sxy]) / (zsh + zst);
    State r;
    r[vn] = bp;
    r[nn] = sign * zpt * bp;
    r[tt] = sign * there.lambda_over_p_speed() * bp;
    r[vt] = bs;
    r[sxy] = sign * zst * bs;
    return r;
  }

  // Against a boundary, the solution beyond continues as the mirror image of the cell: its wave
  // leaves into an identical medium, and the image's mirrored fluctuation sends its wave back in.
  static State transverse_at_boundary(BoundaryKind kind, int axis, const State& w,
                                      const Material& m, bool up) {
    return transverse(axis, w, m, m, up) + transverse(axis, reflect(kind, axis, w), m, m, !up);
  }

  // The mirror image under a boundary normal to `axis`: the linear part of the ghost rule (the
  // ghost is built from it), used by CTU's mirror rule.
  static State reflect(BoundaryKind kind, int axis, const State& w) {
    State r = w;
    switch (kind) {
      case BoundaryKind::free:
      case BoundaryKind::traction:
        r[normal_stress(axis)] = -w[normal_stress(axis)];
        r[sxy] = -w[sxy];
        break;
      case BoundaryKind::fixed:
      case BoundaryKind::velocity:
        r[vx] = -w[vx];
        r[vy] = -w[vy];
        break;
      case BoundaryKind::roller:
        r[normal_velocity(axis)] = -w[normal_velocity(axis)];
        r[sxy] = -w[sxy];
        break;
    }
    return r;
  }

  // --- MPM's constitutive part ------------------------------------------------------------------
  static Eigen::Matrix2d stress_tensor(const State& q, const Material& m) {
    Eigen::Matrix2d s;
    s << q[sxx], q[sxy], q[sxy], q[syy];
    return m.density * s;
  }
  // sigma += dt C : sym(grad v), grad_v(i, j) = dv_i / dx_j, in specific form.
  template <class Q>
  static void add_stress_rate(Q&& q, const Eigen::Matrix2d& grad_v, const Material& m, double dt) {
    const double exx = grad_v(0, 0), eyy = grad_v(1, 1), exy = 0.5 * (grad_v(0, 1) + grad_v(1, 0));
    const double k = dt / m.density;
    q[sxx] += k * (m.p_modulus() * exx + m.lambda() * eyy);
    q[syy] += k * (m.lambda() * exx + m.p_modulus() * eyy);
    q[sxy] += k * 2.0 * m.mu() * exy;
  }

  // The stress tensor of a physical state with sigma_zz, and its strain (eps_zz = 0 up to
  // round-off), for outputs.
  template <class Z>
  static Eigen::Matrix3d stress_tensor_3d(const State& s, const Material& m, const Z& z) {
    Eigen::Matrix3d t;
    t << s[sxx], s[sxy], 0, s[sxy], s[syy], 0, 0, 0, sigma_zz(s, m, z);
    return t;
  }
  template <class Z>
  static Eigen::Matrix3d strain_tensor(const State& s, const Z& z, const Material& m) {
    return physics::isotropic_strain(stress_tensor_3d(s, m, z), m.lambda(), m.mu());
  }

  // --- energy (per unit mass) ------------------------------------------------------------------
  static double kinetic_energy_per_mass(const State& q) {
    return 0.5 * (q[vx] * q[vx] + q[vy] * q[vy]);
  }
  // sigma : epsilon / (2 rho) with the in-plane strains of the plane-strain law.
  static double elastic_energy_per_mass(const State& q, const Material& m) {
    const double sx = q[sxx] * m.density, sy = q[syy] * m.density, s = q[sxy] * m.density;
    const double l2m = m.p_modulus(), l = m.lambda();
    const double det = l2m * l2m - l * l;
    const double ex = (l2m * sx - l * sy) / det, ey = (l2m * sy - l * sx) / det;
    return 0.5 * (sx * ex + sy * ey + s * s / m.mu()) / m.density;
  }
  static double energy_per_mass(const State& q, const Material& m) {
    return kinetic_energy_per_mass(q) + elastic_energy_per_mass(q, m);
  }

 private:
  // 1D star state of a (sigma, v) pair with impedances zm, zp (docs/method.md, "Fluxes"); inv is
  // 1 / (zm + zp).
  static void pair_star(double zm, double sm, double vm, double zp, double sp, double vp,
                        double inv, double& s_star, double& v_star) {
    v_star = (zm * vm + zp * vp + sp - sm) * inv;
    s_star = (zp * sm + zm * sp + zm * zp * (vp - vm)) * inv;
  }
};

}  // namespace dgmpm
