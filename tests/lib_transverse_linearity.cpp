// lib/: CTU's transverse split is linear in the fluctuation it splits, for every physics with
// corner transport: T(a w1 + b w2) = a T(w1) + b T(w2), between two media and against each kind of
// boundary, along both axes, up and down. The operator relies on it: it sums the fluctuations
// entering a cell and splits the sum once (DGOperator::transverse_correction).
#define BOOST_TEST_MODULE transverse_linearity
#include <boost/test/unit_test.hpp>

#include <dgmpm/physics/advection.hpp>
#include <dgmpm/physics/contract.hpp>
#include <dgmpm/physics/finite_strain_plane.hpp>
#include <dgmpm/physics/hyperelastic_laws.hpp>
#include <dgmpm/physics/plane_strain.hpp>
#include <dgmpm/physics/plane_strain_plastic.hpp>

#include <random>
#include <string>

using namespace dgmpm;

namespace {

constexpr BoundaryKind kinds[] = {BoundaryKind::free, BoundaryKind::traction, BoundaryKind::fixed,
                                  BoundaryKind::velocity, BoundaryKind::roller};

// Largest |T(a w1 + b w2) - a T(w1) - b T(w2)| over random w1, w2, a, b, relative to the size of
// the parts, for the split `split(axis, w, up, kind)` (kind unused between two media).
template <class P, class Split>
double nonlinearity(const Split& split, std::mt19937& gen) {
  using State = typename P::State;
  std::uniform_real_distribution<double> u(-1.0, 1.0);
  double worst = 0.0;
  int nonzero = 0;
  for (int trial = 0; trial < 20; ++trial)
    for (int axis = 0; axis < 2; ++axis)
      for (bool up : {false, true})
        for (BoundaryKind kind : kinds) {
          State w1, w2;
          for (int i = 0; i < P::n_comp; ++i) {
            w1[i] = u(gen);
            w2[i] = u(gen);
          }
          const double a = 3 * u(gen), b = 3 * u(gen);
          const State t1 = split(axis, w1, up, kind), t2 = split(axis, w2, up, kind);
          const State sum = split(axis, State(a * w1 + b * w2), up, kind);
          // (A split may be 0: advection sends nothing against its speed, nor back off a fixed
          // boundary; then the sum's must be exactly 0.)
          const double scale = (a * t1).norm() + (b * t2).norm();
          const double defect = (sum - a * t1 - b * t2).norm();
          worst = std::max(worst, scale > 0.0 ? defect / scale : defect);
          nonzero += scale > 0.0;
        }
  BOOST_TEST(nonzero > 0);
  return worst;
}

// Between `here` and `there`, and against each boundary from `here`.
template <class P, class Medium>
void check(const Medium& here, const Medium& there, const std::string& what) {
  std::mt19937 gen(7);
  const double across =
      nonlinearity<P>([&](int axis, const typename P::State& w, bool up,
                          BoundaryKind) { return P::transverse(axis, w, here, there, up); },
                      gen);
  BOOST_TEST(across < 1e-14, what << ": transverse is not linear (" << across << ")");
  const double boundary = nonlinearity<P>(
      [&](int axis, const typename P::State& w, bool up, BoundaryKind kind) {
        return P::transverse_at_boundary(kind, axis, w, here, up);
      },
      gen);
  BOOST_TEST(boundary < 1e-14,
             what << ": transverse_at_boundary is not linear (" << boundary << ")");
}

}  // namespace

BOOST_AUTO_TEST_CASE(small_strain_plane_strain) {
  static_assert(physics::CornerTransport<PlaneStrain>);
  check<PlaneStrain>(PlaneStrain::Material(2e11, 0.3, 7800),
                     PlaneStrain::Material(7e10, 0.33, 2700), "plane strain, steel | aluminium");
  check<PlaneStrainPlastic>(PlaneStrainPlastic::Material(2e11, 0.3, 7800),
                            PlaneStrainPlastic::Material(2e6, 0.45, 1000),
                            "plastic plane strain, stiff | soft (1e5)");
}

BOOST_AUTO_TEST_CASE(advection) {
  Advection<2>::Material a, b;
  a.speed << 1.0, -0.5;
  b.speed << -0.25, 2.0;
  check<Advection<2>>(a, b, "advection");
}

// The media of finite strain are linearised at the cells' edge states: strained, sheared, rotated.
template <class Law>
void check_finite_strain(const std::string& law) {
  using P = FiniteStrainPlane<Law>;
  static_assert(physics::CornerTransport<P>);
  const HyperelasticMaterial steel(2e11, 0.3, 7800), soft(1e9, 0.45, 1100);
  Eigen::Matrix2d f1, f2;
  f1 << 1.08, 0.05, -0.03, 0.95;
  f2 << 0.9, -0.12, 0.2, 1.15;
  for (int axis = 0; axis < 2; ++axis) {
    const auto here = P::transverse_medium(axis, P::specific(f1, {1.0, -2.0}, steel), steel);
    const auto there = P::transverse_medium(axis, P::specific(f2, {0.5, 3.0}, soft), soft);
    check<P>(here, there, law + " finite strain, medium along axis " + std::to_string(axis));
  }
}

BOOST_AUTO_TEST_CASE(finite_strain_plane) {
  check_finite_strain<SaintVenantKirchhoff>("Saint Venant-Kirchhoff");
  check_finite_strain<NeoHookean>("neo-Hookean");
}
