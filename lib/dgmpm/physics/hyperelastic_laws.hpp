#pragma once
// Hyperelastic laws for finite strain (docs/method.md, "Finite strain"), as compile-time
// parameters of a finite-strain physics: the strain energy W(F) per unit reference volume, the
// nominal stress P = dW/dF and its tangent dP/dF. So far their uniaxial-strain forms,
// F = diag(F, 1, 1), with P the xx component (the 1D physics, finite_strain_bar.hpp).
//   Saint Venant-Kirchhoff: W = (lambda/2) (tr E)^2 + mu E : E, E = (F^T F - I) / 2; uniaxially
//     W = (M/8) (F^2 - 1)^2, P = (M/2) F (F^2 - 1), M = lambda + 2 mu: hyperbolic for
//     F > 1/sqrt(3) only (dP/dF = (M/2) (3 F^2 - 1)).
//   Neo-Hookean: W = (mu/2) (J^(-2/3) tr(F^T F) - 3) + (kappa/2) (J - 1)^2, J = det F,
//     kappa = lambda + 2 mu / 3; uniaxially P = (2 mu / 3) F^(-5/3) (F^2 - 1) + kappa (F - 1),
//     dP/dF = (2 mu / 9) F^(-8/3) (F^2 + 5) + kappa, positive for every F > 0.
// Both reduce to small-strain elasticity with the Lame moduli at F = I (dP/dF = M).
// Uniaxially the Cauchy stress is diag(P, s_l, s_l): sigma_xx = P F / J = P, and the lateral
// s_l = sigma_yy = sigma_zz (uniaxial_lateral_stress; SVK lambda (F^2 - 1) / (2 F), neo-Hookean
// mu F^(-5/3) (1 - F^2) / 3 + kappa (F - 1)). `uniaxial_lowest_f`: where the longitudinal
// tangent vanishes (the hyperbolic range is F above it).
//
// Plane strain (F_zz = 1, F the in-plane 2 x 2 block): the in-plane energy, nominal stress and
// tangent A_iJkL = dP_iJ / dF_kL (plane_*), and the full Cauchy stress with sigma_zz
// (plane_cauchy). SVK: P = F S, S = lambda tr(E) I + 2 mu E with E the in-plane Green-Lagrange
// strain (E_zz = 0), A_iJkL = delta_ik S_JL + lambda F_iJ F_kL + mu (F_iL F_kJ + (F F^T)_ik
// delta_JL). Neo-Hookean, with G = F^-T, I1 = tr(F^T F) + 1 and a = J^(-2/3):
// P = mu a (F - (I1 / 3) G) + kappa J (J - 1) G.

#include <Eigen/Core>
#include <Eigen/LU>
#include <array>
#include <cmath>

namespace dgmpm {

// A plane-strain tangent A_iJkL, i, J, k, L in {x, y}, stored as a[i][J][k][L].
using PlaneTangent = std::array<std::array<std::array<std::array<double, 2>, 2>, 2>, 2>;

// What an edge normal to an axis needs of a law at F: the traction P e_axis and the acoustic
// tensor A_ik = A_i,axis,k,axis (plane_edge: the same values as plane_stress and plane_tangent
// give, with only the terms they need).
struct PlaneEdge {
  Eigen::Vector2d traction;
  Eigen::Matrix2d acoustic;
};

// The Lame moduli of a law, from Young's modulus and Poisson's ratio.
struct LameModuli {
  double lambda = 0, mu = 0;
  static LameModuli from_young(double young, double poisson) {
    return {young * poisson / ((1 + poisson) * (1 - 2 * poisson)), young / (2 * (1 + poisson))};
  }
  double p_modulus() const { return lambda + 2 * mu; }
};

// A finite-strain material (1D and 2D alike): the law's moduli and the reference density rho0.
struct HyperelasticMaterial {
  HyperelasticMaterial() : HyperelasticMaterial(1.0, 0.0, 1.0) {}
  HyperelasticMaterial(double young, double poisson, double density)
      : young(young), poisson(poisson), density(density),
        moduli(LameModuli::from_young(young, poisson)) {}
  double young, poisson, density;
  LameModuli moduli;

  // A cell holding two materials: the density of their mass over their volume and the moduli
  // weighted by mass (the same material when both are).
  static HyperelasticMaterial blend(const HyperelasticMaterial& a, double ma,
                                    const HyperelasticMaterial& b, double mb) {
    const double w = mb / (ma + mb);
    HyperelasticMaterial m = a;
    m.density = (ma + mb) / (ma / a.density + mb / b.density);
    m.moduli.lambda = (1 - w) * a.moduli.lambda + w * b.moduli.lambda;
    m.moduli.mu = (1 - w) * a.moduli.mu + w * b.moduli.mu;
    return m;
  }
};

struct SaintVenantKirchhoff {
  static constexpr const char* name = "saint_venant_kirchhoff";
  static double uniaxial_energy(double f, const LameModuli& k) {
    const double g = f * f - 1;
    return 0.125 * k.p_modulus() * g * g;
  }
  static double uniaxial_stress(double f, const LameModuli& k) {
    return 0.5 * k.p_modulus() * f * (f * f - 1);
  }
  static double uniaxial_tangent(double f, const LameModuli& k) {
    return 0.5 * k.p_modulus() * (3 * f * f - 1);
  }
  static double uniaxial_lateral_stress(double f, const LameModuli& k) {
    return 0.5 * k.lambda * (f * f - 1) / f;
  }
  static double uniaxial_lowest_f() { return 1 / std::sqrt(3.0); }

  static Eigen::Matrix2d plane_green(const Eigen::Matrix2d& f) {
    return 0.5 * (f.transpose() * f - Eigen::Matrix2d::Identity());
  }
  static Eigen::Matrix2d plane_second(const Eigen::Matrix2d& f, const LameModuli& k) {
    const Eigen::Matrix2d e = plane_green(f);
    return k.lambda * e.trace() * Eigen::Matrix2d::Identity() + 2 * k.mu * e;
  }
  static double plane_energy(const Eigen::Matrix2d& f, const LameModuli& k) {
    const Eigen::Matrix2d e = plane_green(f);
    return 0.5 * k.lambda * e.trace() * e.trace() + k.mu * (e.array() * e.array()).sum();
  }
  static Eigen::Matrix2d plane_stress(const Eigen::Matrix2d& f, const LameModuli& k) {
    return f * plane_second(f, k);
  }
  static PlaneTangent plane_tangent(const Eigen::Matrix2d& f, const LameModuli& k) {
    const Eigen::Matrix2d s = plane_second(f, k), b = f * f.transpose();
    PlaneTangent a{};
    for (int i = 0; i < 2; ++i)
      for (int J = 0; J < 2; ++J)
        for (int kk = 0; kk < 2; ++kk)
          for (int L = 0; L < 2; ++L)
            a[i][J][kk][L] = (i == kk ? s(J, L) : 0.0) + k.lambda * f(i, J) * f(kk, L) +
                             k.mu * (f(i, L) * f(kk, J) + (J == L ? b(i, kk) : 0.0));
    return a;
  }
  static PlaneEdge plane_edge(const Eigen::Matrix2d& f, int axis, const LameModuli& k) {
    const Eigen::Matrix2d s = plane_second(f, k), b = f * f.transpose();
    const Eigen::Vector2d fa = f.col(axis);
    return {f * s.col(axis), s(axis, axis) * Eigen::Matrix2d::Identity() +
                                 (k.lambda + k.mu) * fa * fa.transpose() + k.mu * b};
  }
  // sigma = P F^T / J in plane, sigma_zz = S_zz / J = lambda tr(E) / J.
  static Eigen::Matrix3d plane_cauchy(const Eigen::Matrix2d& f, const LameModuli& k) {
    const double j = f.determinant();
    Eigen::Matrix3d sigma = Eigen::Matrix3d::Zero();
    sigma.topLeftCorner<2, 2>() = plane_stress(f, k) * f.transpose() / j;
    sigma(2, 2) = k.lambda * plane_green(f).trace() / j;
    return sigma;
  }
};

struct NeoHookean {
  static constexpr const char* name = "neo_hookean";
  static double bulk(const LameModuli& k) { return k.lambda + 2.0 * k.mu / 3.0; }
  static double uniaxial_energy(double f, const LameModuli& k) {
    const double j = f;
    return 0.5 * k.mu * (std::pow(j, -2.0 / 3.0) * (f * f + 2) - 3) +
           0.5 * bulk(k) * (j - 1) * (j - 1);
  }
  static double uniaxial_stress(double f, const LameModuli& k) {
    return 2.0 * k.mu / 3.0 * std::pow(f, -5.0 / 3.0) * (f * f - 1) + bulk(k) * (f - 1);
  }
  static double uniaxial_tangent(double f, const LameModuli& k) {
    return 2.0 * k.mu / 9.0 * std::pow(f, -8.0 / 3.0) * (f * f + 5) + bulk(k);
  }
  static double uniaxial_lateral_stress(double f, const LameModuli& k) {
    return k.mu / 3.0 * std::pow(f, -5.0 / 3.0) * (1 - f * f) + bulk(k) * (f - 1);
  }
  static double uniaxial_lowest_f() { return 0.0; }

  static double plane_energy(const Eigen::Matrix2d& f, const LameModuli& k) {
    const double j = f.determinant(), i1 = (f.array() * f.array()).sum() + 1;
    return 0.5 * k.mu * (std::pow(j, -2.0 / 3.0) * i1 - 3) + 0.5 * bulk(k) * (j - 1) * (j - 1);
  }
  static Eigen::Matrix2d plane_stress(const Eigen::Matrix2d& f, const LameModuli& k) {
    const double j = f.determinant(), i1 = (f.array() * f.array()).sum() + 1;
    const Eigen::Matrix2d g = f.inverse().transpose();
    return k.mu * std::pow(j, -2.0 / 3.0) * (f - i1 / 3 * g) + bulk(k) * j * (j - 1) * g;
  }
  // d(J^-2/3) = -(2/3) J^-2/3 G : dF, dI1 = 2 F : dF, dG_iJ = -G_iL G_kJ dF_kL,
  // dJ = J G : dF.
  static PlaneTangent plane_tangent(const Eigen::Matrix2d& f, const LameModuli& k) {
    const double j = f.determinant(), i1 = (f.array() * f.array()).sum() + 1;
    const double a = std::pow(j, -2.0 / 3.0), kappa = bulk(k);
    const Eigen::Matrix2d g = f.inverse().transpose();
    PlaneTangent t{};
    for (int i = 0; i < 2; ++i)
      for (int J = 0; J < 2; ++J)
        for (int kk = 0; kk < 2; ++kk)
          for (int L = 0; L < 2; ++L) {
            const double dev = (i == kk && J == L ? 1.0 : 0.0) - 2.0 / 3.0 * f(i, J) * g(kk, L) -
                               2.0 / 3.0 * f(kk, L) * g(i, J) +
                               2.0 / 9.0 * i1 * g(kk, L) * g(i, J) + i1 / 3 * g(i, L) * g(kk, J);
            const double vol =
                (2 * j - 1) * j * g(kk, L) * g(i, J) - j * (j - 1) * g(i, L) * g(kk, J);
            t[i][J][kk][L] = k.mu * a * dev + kappa * vol;
          }
    return t;
  }
  // Along J = L = axis the tangent's terms gather into
  // A = mu a (I - (2/3) (f g^T + g f^T) + (5/9) I1 g g^T) + kappa J^2 g g^T, f = F e_axis,
  // g = G e_axis.
  static PlaneEdge plane_edge(const Eigen::Matrix2d& f, int axis, const LameModuli& k) {
    const double j = f.determinant(), i1 = f.squaredNorm() + 1;
    const double a = std::pow(j, -2.0 / 3.0), kappa = bulk(k);
    // G = F^-T, column `axis` only.
    const Eigen::Vector2d g =
        axis == 0 ? Eigen::Vector2d(f(1, 1), -f(0, 1)) / j : Eigen::Vector2d(-f(1, 0), f(0, 0)) / j;
    const Eigen::Vector2d fa = f.col(axis);
    const Eigen::Matrix2d fg = fa * g.transpose();
    return {k.mu * a * (fa - i1 / 3 * g) + kappa * j * (j - 1) * g,
            k.mu * a *
                    (Eigen::Matrix2d::Identity() - 2.0 / 3.0 * (fg + fg.transpose()) +
                     5.0 / 9.0 * i1 * g * g.transpose()) +
                kappa * j * j * g * g.transpose()};
  }
  // sigma = mu J^(-5/3) dev(b) + kappa (J - 1) I, b = F F^T with b_zz = 1.
  static Eigen::Matrix3d plane_cauchy(const Eigen::Matrix2d& f, const LameModuli& k) {
    const double j = f.determinant();
    Eigen::Matrix3d b = Eigen::Matrix3d::Identity();
    b.topLeftCorner<2, 2>() = f * f.transpose();
    const Eigen::Matrix3d dev = b - b.trace() / 3 * Eigen::Matrix3d::Identity();
    return k.mu * std::pow(j, -5.0 / 3.0) * dev + bulk(k) * (j - 1) * Eigen::Matrix3d::Identity();
  }
};

}  // namespace dgmpm
