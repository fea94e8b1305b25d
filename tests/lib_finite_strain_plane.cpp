// lib/: the plane-strain forms of the hyperelastic laws (F_zz = 1) and their acoustic tensor, the
// ground 2D finite strain stands on. Against independent routes written here: the 3D energies of
// the laws (SVK from E, neo-Hookean from J and I1, with a unit F_zz), differentiated by central
// differences for P = dW/dF and A = dP/dF; the uniaxial forms of the 1D physics along x; small
// strain at F = I (A(e_x) = diag(lambda + 2 mu, mu)); frame invariance (P(QF) = Q P(F),
// A(QF, N) = Q A(F, N) Q^T); the symmetric Cauchy stress; the impedance's square; the largest
// wave speed over directions against a dense scan; and CTU's transverse split of the 2D physics.
#define BOOST_TEST_MODULE finite_strain_plane
#include <boost/test/unit_test.hpp>

#include <dgmpm/physics/acoustic.hpp>
#include <dgmpm/physics/finite_strain_plane.hpp>
#include <dgmpm/physics/hyperelastic_laws.hpp>
#include <dgmpm/physics/plane_strain.hpp>

#include <Eigen/Dense>
#include <Eigen/Geometry>
#include <cmath>
#include <limits>
#include <random>
#include <vector>

using namespace dgmpm;

namespace {

constexpr double E = 2e11, nu = 0.3, rho0 = 7800;
const LameModuli k = LameModuli::from_young(E, nu);
const double M = k.lambda + 2 * k.mu, kappa = k.lambda + 2 * k.mu / 3;

// The 3D energies, with F = [[F, 0], [0, 1]].
double svk_energy(const Eigen::Matrix2d& f) {
  Eigen::Matrix3d g = Eigen::Matrix3d::Identity();
  g.topLeftCorner<2, 2>() = f;
  const Eigen::Matrix3d e = 0.5 * (g.transpose() * g - Eigen::Matrix3d::Identity());
  return 0.5 * k.lambda * e.trace() * e.trace() + k.mu * (e * e.transpose()).trace();
}
double nh_energy(const Eigen::Matrix2d& f) {
  Eigen::Matrix3d g = Eigen::Matrix3d::Identity();
  g.topLeftCorner<2, 2>() = f;
  const double j = g.determinant();
  return 0.5 * k.mu * (std::pow(j, -2.0 / 3.0) * (g.transpose() * g).trace() - 3) +
         0.5 * kappa * (j - 1) * (j - 1);
}

// Deformation gradients near I and far from it (stretches to 1.5, shears to 0.4, J from 0.6).
std::vector<Eigen::Matrix2d> gradients() {
  std::mt19937 gen(7);
  std::uniform_real_distribution<double> u(-0.4, 0.4);
  std::vector<Eigen::Matrix2d> out{Eigen::Matrix2d::Identity()};
  for (int n = 0; n < 12; ++n) {
    const double scale = n < 4 ? 0.01 : 1.0;
    Eigen::Matrix2d f = Eigen::Matrix2d::Identity();
    for (int i = 0; i < 4; ++i) f(i / 2, i % 2) += scale * u(gen);
    if (f.determinant() > 0.6) out.push_back(f);
  }
  return out;
}

template <class Law, class W>
void check_derivatives(const W& energy) {
  const double d = 1e-6;
  for (const Eigen::Matrix2d& f : gradients()) {
    const Eigen::Matrix2d p = Law::plane_stress(f, k);
    const PlaneTangent a = Law::plane_tangent(f, k);
    BOOST_TEST(Law::plane_energy(f, k) == energy(f), boost::test_tools::tolerance(1e-9));
    for (int kk = 0; kk < 2; ++kk)
      for (int L = 0; L < 2; ++L) {
        Eigen::Matrix2d df = Eigen::Matrix2d::Zero();
        df(kk, L) = d;
        // P = dW/dF and A = dP/dF by central differences, to 1e-6 of M (truncation d^2, round-off
        // 1e-16 / d of the energies' scale).
        BOOST_TEST(std::abs(p(kk, L) - (energy(f + df) - energy(f - df)) / (2 * d)) <= 1e-6 * M);
        const Eigen::Matrix2d dp =
            (Law::plane_stress(f + df, k) - Law::plane_stress(f - df, k)) / (2 * d);
        for (int i = 0; i < 2; ++i)
          for (int J = 0; J < 2; ++J) {
            BOOST_TEST(std::abs(a[i][J][kk][L] - dp(i, J)) <= 1e-6 * M);
            BOOST_TEST(std::abs(a[i][J][kk][L] - a[kk][L][i][J]) <= 1e-12 * M);  // major symmetry
          }
      }
  }
}

Eigen::Matrix2d rotation(double t) {
  Eigen::Matrix2d q;
  q << std::cos(t), -std::sin(t), std::sin(t), std::cos(t);
  return q;
}

template <class Law>
void check_invariance() {
  for (const Eigen::Matrix2d& f : gradients()) {
    const Eigen::Matrix2d q = rotation(0.7);
    const Eigen::Matrix2d p = Law::plane_stress(f, k), pq = Law::plane_stress(q * f, k);
    BOOST_TEST((pq - q * p).norm() <= 1e-12 * M);
    const Eigen::Vector2d n(std::cos(0.3), std::sin(0.3));
    const Eigen::Matrix2d a = acoustic_tensor(Law::plane_tangent(f, k), n);
    const Eigen::Matrix2d aq = acoustic_tensor(Law::plane_tangent(q * f, k), n);
    BOOST_TEST((aq - q * a * q.transpose()).norm() <= 1e-11 * M);
    const Eigen::Matrix3d sigma = Law::plane_cauchy(f, k);
    BOOST_TEST(std::abs(sigma(0, 1) - sigma(1, 0)) <= 1e-12 * M);  // balance of angular momentum
    // In plane, sigma = P F^T / J.
    const Eigen::Matrix2d in_plane = p * f.transpose() / f.determinant();
    BOOST_TEST((sigma.topLeftCorner<2, 2>() - in_plane).norm() <= 1e-12 * M);
  }
}

}  // namespace

BOOST_AUTO_TEST_CASE(stress_and_tangent_are_the_energy_derivatives) {
  check_derivatives<SaintVenantKirchhoff>(svk_energy);
  check_derivatives<NeoHookean>(nh_energy);
}

BOOST_AUTO_TEST_CASE(laws_are_frame_invariant_with_symmetric_cauchy_stress) {
  check_invariance<SaintVenantKirchhoff>();
  check_invariance<NeoHookean>();
}

// What an edge needs (plane_edge: the traction and the acoustic tensor along an axis, with only
// the terms they need) is the column of the stress and the contraction of the tangent.
BOOST_AUTO_TEST_CASE(edge_values_are_the_stress_and_tangent_along_the_axis) {
  const auto check = [&](auto law) {
    using Law = decltype(law);
    for (const Eigen::Matrix2d& f : gradients())
      for (int axis = 0; axis < 2; ++axis) {
        const PlaneEdge e = Law::plane_edge(f, axis, k);
        const Eigen::Vector2d n = Eigen::Vector2d::Unit(axis);
        BOOST_TEST((e.traction - Law::plane_stress(f, k).col(axis)).norm() <= 1e-13 * M);
        BOOST_TEST((e.acoustic - acoustic_tensor(Law::plane_tangent(f, k), n)).norm() <= 1e-13 * M);
      }
  };
  check(SaintVenantKirchhoff{});
  check(NeoHookean{});
}

// Along x with F = diag(f, 1) the plane forms are the 1D physics' uniaxial ones, and sigma_zz
// its lateral stress.
BOOST_AUTO_TEST_CASE(uniaxial_deformation_gives_the_1d_forms) {
  for (double f : {0.8, 1.0, 1.07, 1.3}) {
    const Eigen::Matrix2d g = Eigen::Vector2d(f, 1.0).asDiagonal();
    const auto check = [&](auto law) {
      using Law = decltype(law);
      BOOST_TEST(Law::plane_stress(g, k)(0, 0) == Law::uniaxial_stress(f, k),
                 boost::test_tools::tolerance(1e-12));
      BOOST_TEST(Law::plane_tangent(g, k)[0][0][0][0] == Law::uniaxial_tangent(f, k),
                 boost::test_tools::tolerance(1e-12));
      const Eigen::Matrix3d sigma = Law::plane_cauchy(g, k);
      BOOST_TEST(std::abs(sigma(1, 1) - Law::uniaxial_lateral_stress(f, k)) <= 1e-12 * M);
      BOOST_TEST(std::abs(sigma(2, 2) - Law::uniaxial_lateral_stress(f, k)) <= 1e-12 * M);
    };
    check(SaintVenantKirchhoff{});
    check(NeoHookean{});
  }
}

// At F = I both laws are small-strain elasticity: A(e_x) = diag(M, mu), speeds c_p and c_s in
// every direction, Z(e_x) = diag(rho0 c_p, rho0 c_s).
BOOST_AUTO_TEST_CASE(small_strain_at_the_reference) {
  const Eigen::Matrix2d id = Eigen::Matrix2d::Identity();
  for (const PlaneTangent& a :
       {SaintVenantKirchhoff::plane_tangent(id, k), NeoHookean::plane_tangent(id, k)}) {
    const Eigen::Matrix2d ax = acoustic_tensor(a, Eigen::Vector2d(1, 0));
    BOOST_TEST(ax(0, 0) == M, boost::test_tools::tolerance(1e-14));
    BOOST_TEST(ax(1, 1) == k.mu, boost::test_tools::tolerance(1e-14));
    BOOST_TEST(std::abs(ax(0, 1)) <= 1e-14 * M);
    const Eigen::Matrix2d z = impedance_tensor(ax, rho0);
    BOOST_TEST(z(0, 0) == std::sqrt(rho0 * M), boost::test_tools::tolerance(1e-14));
    BOOST_TEST(z(1, 1) == std::sqrt(rho0 * k.mu), boost::test_tools::tolerance(1e-14));
    BOOST_TEST(max_wave_speed(a, rho0) == std::sqrt(M / rho0), boost::test_tools::tolerance(1e-14));
  }
}

// Z is the symmetric root of rho0 A; the largest speed over directions is at least a dense scan's
// and within its resolution; a tangent that is not positive definite gives NaN.
BOOST_AUTO_TEST_CASE(impedance_and_largest_speed) {
  for (const Eigen::Matrix2d& f : gradients())
    for (const PlaneTangent& a :
         {SaintVenantKirchhoff::plane_tangent(f, k), NeoHookean::plane_tangent(f, k)}) {
      const Eigen::Matrix2d q = acoustic_tensor(a, Eigen::Vector2d(0.6, 0.8));
      const Eigen::Matrix2d z = impedance_tensor(q, rho0);
      BOOST_TEST((z - z.transpose()).norm() <= 1e-12 * z.norm());
      BOOST_TEST((z * z - rho0 * q).norm() <= 1e-12 * rho0 * q.norm());
      double scan = 0;
      constexpr int kScan = 20000;  // lambda_max within (pi / kScan)^2 / 2 relative of the max
      for (int s = 0; s < kScan; ++s) {
        const double t = M_PI * s / kScan;
        const Eigen::Matrix2d qt = acoustic_tensor(a, Eigen::Vector2d(std::cos(t), std::sin(t)));
        scan = std::max(scan, Eigen::SelfAdjointEigenSolver<Eigen::Matrix2d>(qt).eigenvalues()[1]);
      }
      const double c = max_wave_speed(a, rho0), c_scan = std::sqrt(scan / rho0);
      BOOST_TEST(c >= c_scan * (1 - 1e-14));
      BOOST_TEST(c <= c_scan * (1 + 1e-8));
    }
  // SVK compressed along a direction between the sampled ones, just past and just before the
  // stretch where some direction loses its real speeds: in plane strain that is 0.70562 (found by
  // the scan, in directions about 35 degrees from the compression), well above the uniaxial
  // 1/sqrt(3) (longitudinal waves only). NaN exactly when a dense scan finds a direction whose
  // acoustic tensor is not positive definite.
  for (const double angle : {0.3, 0.77, 1.1, 2.9})
    for (const double stretch : {0.7051, 0.7061}) {
      const Eigen::Matrix2d r = Eigen::Rotation2Dd(angle).toRotationMatrix();
      const Eigen::Matrix2d f = r * Eigen::Vector2d(stretch, 1.0).asDiagonal() * r.transpose();
      const PlaneTangent a = SaintVenantKirchhoff::plane_tangent(f, k);
      double least = std::numeric_limits<double>::infinity();
      for (int s = 0; s < 20000; ++s) {
        const double t = M_PI * s / 20000;
        const Eigen::Matrix2d q = acoustic_tensor(a, Eigen::Vector2d(std::cos(t), std::sin(t)));
        least = std::min(least, Eigen::SelfAdjointEigenSolver<Eigen::Matrix2d>(q).eigenvalues()[0]);
      }
      BOOST_TEST((least < 0) == (stretch < 0.7056));
      BOOST_TEST(std::abs(least) > 1e-6 * M);
      BOOST_TEST(std::isnan(max_wave_speed(a, rho0)) == (least < 0), angle << ' ' << stretch);
    }
  // SVK compressed uniaxially past 1/sqrt(3): no real longitudinal speed.
  const Eigen::Matrix2d crushed = Eigen::Vector2d(0.5, 1.0).asDiagonal();
  const PlaneTangent a = SaintVenantKirchhoff::plane_tangent(crushed, k);
  BOOST_TEST(std::isnan(max_wave_speed(a, rho0)));
  BOOST_TEST(std::isnan(impedance_tensor(acoustic_tensor(a, Eigen::Vector2d(1, 0)), rho0)(0, 0)));
}

// CTU's transverse split (FiniteStrainPlane::transverse): a fluctuation w = (dF, dv) split into the
// waves of the Jacobian B along the crossed axis. Checked against (1) B w itself, -(dv (x) N,
// dP[dF] N) with dP from central differences of the stress: the up and down parts' fluxes sum to
// it; (2) the waves built here from the acoustic tensor's eigenvectors (Eigen's solver): a wave
// moving up is all up, none down; (3) small strain at F = I (PlaneStrain::transverse, written for
// stresses), between two materials; (4) each boundary's condition on the wave and its reflection.
namespace {

template <class Law>
using Plane = FiniteStrainPlane<Law>;

template <class Law>
typename Plane<Law>::State state_of(const Eigen::Matrix2d& f, const Eigen::Vector2d& v,
                                    const HyperelasticMaterial& m) {
  return Plane<Law>::specific(f, v, m);
}

// B w along `axis` for a rate w of (F, v): the flux's linearisation, a rate of the conserved
// (F, rho0 v), with dP from central differences of P.
template <class Law>
Eigen::Matrix<double, 6, 1> jacobian_times(int axis, const Eigen::Matrix2d& f,
                                           const Eigen::Matrix<double, 6, 1>& w) {
  Eigen::Matrix2d df;
  df << w[0], w[1], w[2], w[3];
  const double h = 1e-6 / std::max(1e-300, df.norm());
  const Eigen::Matrix2d dp =
      (Law::plane_stress(f + h * df, k) - Law::plane_stress(f - h * df, k)) / (2 * h);
  Eigen::Matrix<double, 6, 1> b = Eigen::Matrix<double, 6, 1>::Zero();
  b[2 * 0 + axis] = -w[4];
  b[2 * 1 + axis] = -w[5];
  b[4] = -dp(0, axis);
  b[5] = -dp(1, axis);
  return b;
}

template <class Law>
void check_transverse_split() {
  using P = Plane<Law>;
  const HyperelasticMaterial m(E, nu, rho0);
  std::mt19937 gen(11);
  std::uniform_real_distribution<double> u(-1.0, 1.0);
  for (const Eigen::Matrix2d& f : gradients())
    for (int axis = 0; axis < 2; ++axis) {
      const typename P::State q = state_of<Law>(f, Eigen::Vector2d(3.0, -2.0), m);
      const auto medium = P::transverse_medium(axis, q, m);
      for (int n = 0; n < 4; ++n) {
        typename P::State w;
        for (int i = 0; i < 6; ++i) w[i] = (i < 4 ? 1e-3 : 10.0) * u(gen);
        const typename P::State r_up = P::transverse(axis, w, medium, medium, true);
        const typename P::State r_down = P::transverse(axis, w, medium, medium, false);
        const typename P::State sum = P::flux(axis, r_up, m) + P::flux(axis, r_down, m);
        const typename P::State expected = jacobian_times<Law>(axis, f, w);
        BOOST_TEST((sum - expected).norm() <= 1e-7 * expected.norm(), axis << ' ' << n);
      }
      // The moving waves, from the acoustic tensor's eigenvectors: dv = e, dF_i,axis = -+e_i / c
      // (to +axis, -axis), the other column of dF free (a zero-speed part).
      const Eigen::Matrix2d a =
          acoustic_tensor(Law::plane_tangent(f, k), Eigen::Vector2d::Unit(axis));
      const Eigen::SelfAdjointEigenSolver<Eigen::Matrix2d> eig(a);
      for (int e = 0; e < 2; ++e)
        for (const bool up : {true, false}) {
          const Eigen::Vector2d dv = eig.eigenvectors().col(e);
          const double c = std::sqrt(eig.eigenvalues()[e] / rho0);
          typename P::State w = P::State::Zero();
          w[2 * 0 + axis] = (up ? -1 : 1) * dv[0] / c;
          w[2 * 1 + axis] = (up ? -1 : 1) * dv[1] / c;
          w.template tail<2>() = dv;
          const typename P::State along = P::transverse(axis, w, medium, medium, up);
          const typename P::State against = P::transverse(axis, w, medium, medium, !up);
          BOOST_TEST((along.template tail<2>() - dv).norm() <= 1e-9);
          BOOST_TEST(against.template tail<2>().norm() <= 1e-9);
          BOOST_TEST(against.template head<2>().norm() <= 1e-9 * rho0 * c);
        }
    }
}

}  // namespace

BOOST_AUTO_TEST_CASE(transverse_split_is_the_jacobian_in_its_waves) {
  check_transverse_split<SaintVenantKirchhoff>();
  check_transverse_split<NeoHookean>();
}

// At F = I, between two materials (soft to stiff and back), the split is small strain's: the
// traction rate is the stress rate C : sym(dF) and the star increments' (t, v) are (sigma_nn,
// sigma_tn, v).
BOOST_AUTO_TEST_CASE(transverse_split_at_the_reference_is_small_strain) {
  using P = Plane<NeoHookean>;
  const HyperelasticMaterial soft(E / 3, 0.25, 2700), stiff(E, nu, rho0);
  const PlaneStrain::Material soft_ss(E / 3, 0.25, 2700), stiff_ss(E, nu, rho0);
  std::mt19937 gen(5);
  std::uniform_real_distribution<double> u(-1.0, 1.0);
  for (int axis = 0; axis < 2; ++axis)
    for (int order = 0; order < 2; ++order) {
      const auto& here = order ? stiff : soft;
      const auto& there = order ? soft : stiff;
      const auto& here_ss = order ? stiff_ss : soft_ss;
      const auto& there_ss = order ? soft_ss : stiff_ss;
      const auto mh = P::transverse_medium(
          axis, P::specific(Eigen::Matrix2d::Identity(), Eigen::Vector2d::Zero(), here), here);
      const auto mt = P::transverse_medium(
          axis, P::specific(Eigen::Matrix2d::Identity(), Eigen::Vector2d::Zero(), there), there);
      for (int n = 0; n < 3; ++n) {
        P::State w;
        for (int i = 0; i < 6; ++i) w[i] = (i < 4 ? 1e-3 : 10.0) * u(gen);
        const double exx = w[0], eyy = w[3], exy = 0.5 * (w[1] + w[2]);
        const double lam = here.moduli.lambda, mu = here.moduli.mu;
        PlaneStrain::State ws;
        ws << (lam + 2 * mu) * exx + lam * eyy, lam * exx + (lam + 2 * mu) * eyy, 2 * mu * exy,
            w[4], w[5];
        for (const bool up : {true, false}) {
          const P::State r = P::transverse(axis, w, mh, mt, up);
          const PlaneStrain::State s = PlaneStrain::transverse(axis, ws, here_ss, there_ss, up);
          const int nn = PlaneStrain::normal_stress(axis);
          const double scale = std::abs(s[nn]) + std::abs(s[PlaneStrain::sxy]);
          BOOST_TEST(std::abs(r[axis] - s[nn]) <= 1e-12 * scale);
          BOOST_TEST(std::abs(r[1 - axis] - s[PlaneStrain::sxy]) <= 1e-12 * scale);
          BOOST_TEST(std::abs(r[4] - s[PlaneStrain::vx]) <=
                     1e-12 * (std::abs(s[3]) + std::abs(s[4])));
          BOOST_TEST(std::abs(r[5] - s[PlaneStrain::vy]) <=
                     1e-12 * (std::abs(s[3]) + std::abs(s[4])));
        }
      }
    }
}

// Against a boundary the outgoing wave and its reflection (a wave into the cell: t = +-Z v the
// other way) together meet the boundary's condition with no load: free and traction t = 0, fixed
// and velocity v = 0, roller v_n = 0 and t_t = 0.
BOOST_AUTO_TEST_CASE(transverse_reflection_meets_the_boundary_condition) {
  using P = Plane<NeoHookean>;
  const HyperelasticMaterial m(E, nu, rho0);
  const Eigen::Matrix2d f = (Eigen::Matrix2d() << 1.1, 0.15, -0.05, 0.92).finished();
  P::State w;
  w << 2e-3, -1e-3, 5e-4, 1.5e-3, 12.0, -7.0;
  for (int axis = 0; axis < 2; ++axis) {
    const auto medium = P::transverse_medium(axis, P::specific(f, Eigen::Vector2d::Zero(), m), m);
    const int n = axis, t = 1 - axis;
    for (const bool up : {true, false}) {
      const P::State out = P::transverse(axis, w, medium, medium, up);
      for (const BoundaryKind kind :
           {BoundaryKind::free, BoundaryKind::traction, BoundaryKind::fixed, BoundaryKind::velocity,
            BoundaryKind::roller}) {
        const P::State r = P::transverse_at_boundary(kind, axis, w, medium, up);
        const Eigen::Vector2d tr = r.head<2>(), vr = r.tail<2>();
        const double ts = std::abs(out[0]) + std::abs(out[1]);
        const double vs = std::abs(out[4]) + std::abs(out[5]);
        // The reflection, r - out, moves the other way: t = +Z v going down (up = true), -Z v up.
        const Eigen::Vector2d back_t = tr - out.head<2>(), back_v = vr - out.tail<2>();
        BOOST_TEST((back_t - (up ? 1.0 : -1.0) * (medium.z * back_v)).norm() <= 1e-12 * ts);
        switch (kind) {
          case BoundaryKind::free:
          case BoundaryKind::traction:
            BOOST_TEST(tr.norm() <= 1e-12 * ts);
            break;
          case BoundaryKind::fixed:
          case BoundaryKind::velocity:
            BOOST_TEST(vr.norm() <= 1e-12 * vs);
            break;
          case BoundaryKind::roller:
            BOOST_TEST(std::abs(vr[n]) <= 1e-12 * vs);
            BOOST_TEST(std::abs(tr[t]) <= 1e-12 * ts);
            break;
        }
      }
    }
  }
}
