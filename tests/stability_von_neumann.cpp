// Von Neumann analysis (docs/method.md, "Stability"): published and expected admissible Courant
// numbers, and independent checks of the one-step map obtained from lib's integrators.
#define BOOST_TEST_MODULE stability_von_neumann
#include <boost/test/unit_test.hpp>

#include "stability/admissible_courant.hpp"
#include "stability/criteria.hpp"
#include "stability/one_step_map.hpp"

#include <Eigen/Eigenvalues>
#include <cmath>
#include <numbers>
#include <random>

using namespace dgmpm::stability;

namespace {

constexpr TimeScheme kSchemes[] = {TimeScheme::euler, TimeScheme::rk2};
constexpr Criterion kCriteria[] = {Criterion::l2, Criterion::monotone};
constexpr Model kModels[] = {Model::advection, Model::elastic};

double limit(const CellLayout& layout, TimeScheme s, Criterion c, Model m) {
  return admissible_courant(layout, s, c, m).courant;
}

}  // namespace

BOOST_AUTO_TEST_CASE(one_particle_per_cell_is_stable_up_to_one) {
  for (int k = 1; k <= 9; ++k)
    for (auto s : kSchemes)
      for (auto c : kCriteria)
        for (auto m : kModels) {
          BOOST_TEST_CONTEXT("xi = " << k / 10.0 << ", " << to_string(s) << ", " << to_string(c)
                                     << ", " << to_string(m)) {
            const CourantResult r = admissible_courant(CellLayout{{k / 10.0}, {}}, s, c, m);
            BOOST_TEST(r.bounded);
            BOOST_TEST(std::abs(r.courant - 1.0) < 1e-6);
          }
        }
}

// A particle a hair from a node leaves the other node a tiny mass share: RK2 carries stage values
// of order 1 / share to the neighbours, and the sampled map's round-off grows as much. C* is
// still 1 (the one-particle map does not depend on the position): the analysis must neither
// fail nor read that round-off as a row sum above 1. (Within 1e-10 of a node lib folds the node.)
BOOST_AUTO_TEST_CASE(one_particle_next_to_a_node_is_stable_up_to_one) {
  for (double d : {1e-5, 3e-6, 1e-6, 3e-7, 1e-8, 1e-9, 3e-10})
    for (double x : {d, 1.0 - d})
      for (auto s : kSchemes)
        for (auto c : kCriteria) {
          BOOST_TEST_CONTEXT("xi = " << x << ", " << to_string(s) << ", " << to_string(c)) {
            const double courant = limit(CellLayout{{x}, {}}, s, c, Model::elastic);
            // Round-off scales like 1e-15 / d; what it may add to the limit is below 1e-4 here.
            BOOST_TEST(std::abs(courant - 1.0) < 1e-4);
          }
        }
}

BOOST_AUTO_TEST_CASE(regular_layouts_euler_monotone_match_the_published_formula) {
  for (int n = 1; n <= 8; ++n)
    for (auto m : kModels) {
      BOOST_TEST_CONTEXT("N = " << n << ", " << to_string(m)) {
        const double expected = (2.0 * n - 1.0) / (2.0 * n * n - 1.0);
        BOOST_TEST(std::abs(limit(regular_layout(n), TimeScheme::euler, Criterion::monotone, m) -
                            expected) < 1e-6);
      }
    }
}

BOOST_AUTO_TEST_CASE(two_regular_particles_euler_l2) {
  for (auto m : kModels) {
    const double c = limit(regular_layout(2), TimeScheme::euler, Criterion::l2, m);
    BOOST_TEST(std::abs(c - 0.686) <= 1e-3, to_string(m) << ": C* = " << c);
  }
}

// docs/method.md, "Stability": just above the limit the growth is weak and at small theta, about
// 5e-4 per step at 2% above it for 2 regular particles with Euler.
BOOST_AUTO_TEST_CASE(growth_just_above_the_two_particle_limit_is_weak) {
  const OneStepMap map = build_one_step_map(regular_layout(2), TimeScheme::euler, Model::advection);
  L2Criterion l2(map);
  const double c =
      1.02 * admissible_courant(map, Criterion::l2, default_search_options(Criterion::l2)).courant;
  double rho = 0.0, theta = 0.0;
  for (int k = 0; k <= 20000; ++k) {
    const double t = std::numbers::pi * k / 20000;
    if (const double r = l2.spectral_radius(c, t); r > rho) rho = r, theta = t;
  }
  BOOST_TEST(rho - 1.0 > 4e-4);
  BOOST_TEST(rho - 1.0 < 6e-4);
  BOOST_TEST(theta < 0.5);
}

BOOST_AUTO_TEST_CASE(asymmetric_layout_limits_differ_by_direction) {
  const CellLayout layout{{0.6083, 0.955}, {}};
  const double right = limit(layout, TimeScheme::euler, Criterion::l2, Model::advection);
  const double left = limit(mirror(layout), TimeScheme::euler, Criterion::l2, Model::advection);
  BOOST_TEST(std::abs(right - 0.738) < 1e-3, "to +x: " << right);
  BOOST_TEST(std::abs(left - 0.807) < 1e-3, "to -x: " << left);
  const CourantResult elastic =
      admissible_courant(layout, TimeScheme::euler, Criterion::l2, Model::elastic);
  BOOST_TEST(std::abs(elastic.courant - right) < 1e-8);
  BOOST_TEST(elastic.direction == "+x");
  BOOST_TEST(std::abs(limit(mirror(layout), TimeScheme::euler, Criterion::l2, Model::elastic) -
                      right) < 1e-8);
}

BOOST_AUTO_TEST_CASE(elastic_limit_is_the_smaller_advection_limit_of_layout_and_mirror) {
  std::mt19937 rng(7);
  std::uniform_real_distribution<double> position(0.02, 0.98), mass(0.5, 2.0);
  std::vector<CellLayout> layouts{{{0.6083, 0.955}, {}}, {{0.1, 0.3, 0.85}, {1, 2, 1}}};
  for (int n = 1; n <= 4; ++n) {
    CellLayout l;
    for (int k = 0; k < n; ++k) l.positions.push_back(position(rng)), l.masses.push_back(mass(rng));
    layouts.push_back(l);
  }
  for (const auto& layout : layouts)
    for (auto s : kSchemes)
      for (auto c : kCriteria) {
        BOOST_TEST_CONTEXT(describe(layout.positions)
                           << ", " << to_string(s) << ", " << to_string(c)) {
          const double plus = limit(layout, s, c, Model::advection);
          const double minus = limit(mirror(layout), s, c, Model::advection);
          BOOST_TEST(std::abs(limit(layout, s, c, Model::elastic) - std::min(plus, minus)) < 1e-8);
        }
      }
}

BOOST_AUTO_TEST_CASE(elastic_characteristic_families_are_the_advection_maps) {
  const CellLayout layout{{0.2, 0.55, 0.9}, {1.0, 3.0, 2.0}};
  for (auto s : kSchemes) {
    const OneStepMap elastic = build_one_step_map(layout, s, Model::elastic);
    const OneStepMap right = build_one_step_map(layout, s, Model::advection);
    const OneStepMap left = build_one_step_map(mirror(layout), s, Model::advection);
    BOOST_TEST_REQUIRE(elastic.families.size() == 2u);  // exactly decoupled
    for (double c : {0.3, 0.9}) {
      const auto& fp = elastic.families[0];
      const auto& fm = elastic.families[1];
      BOOST_TEST(fp.direction == "+x");
      BOOST_TEST(fm.direction == "-x");
      BOOST_TEST_REQUIRE(fp.offsets == right.families[0].offsets);
      for (std::size_t i = 0; i < fp.offsets.size(); ++i)
        BOOST_TEST((fp.block(i, c) - right.families[0].block(i, c)).norm() < 1e-13);
      // Reflection x -> -x turns offset d into -d.
      const auto& fl = left.families[0];
      BOOST_TEST_REQUIRE(fm.offsets.size() == fl.offsets.size());
      for (std::size_t i = 0; i < fm.offsets.size(); ++i) {
        const std::size_t j = fm.offsets.size() - 1 - i;
        BOOST_TEST(fm.offsets[i] == -fl.offsets[j]);
        BOOST_TEST((fm.block(i, c) - fl.block(j, c)).norm() < 1e-13);
      }
    }
  }
}

// Hand formula, as an independent check of the map read from lib: one particle per cell with
// Euler is the first-order upwind scheme u_p -= C (u_p - u_{p-1}), wherever the particle sits.
BOOST_AUTO_TEST_CASE(one_particle_euler_map_is_upwind) {
  for (double xi : {0.0, 0.3, 0.5, 0.8, 1.0}) {
    const OneStepMap map =
        build_one_step_map(CellLayout{{xi}, {}}, TimeScheme::euler, Model::advection);
    const auto& f = map.families[0];
    BOOST_TEST_REQUIRE((f.offsets == std::vector<int>{0, 1}));
    for (double c : {0.25, 0.7}) {
      BOOST_TEST(std::abs(f.block(0, c)(0, 0) - (1.0 - c)) < 1e-14);
      BOOST_TEST(std::abs(f.block(1, c)(0, 0) - c) < 1e-14);
    }
  }
}

BOOST_AUTO_TEST_CASE(map_reaches_one_cell_and_conserves) {
  const CellLayout layout{{0.15, 0.4, 0.7, 0.95}, {1, 2, 1, 0.5}};
  for (auto s : kSchemes) {
    const OneStepMap map = build_one_step_map(layout, s, Model::advection);
    const auto& f = map.families[0];
    BOOST_TEST(
        (f.offsets == std::vector<int>{0, 1}));  // docs/method.md, "Stability": d = 0, 1 only
    BOOST_TEST(map.degree == (s == TimeScheme::euler ? 1 : 2));
    // A constant state is preserved: every row of the full map sums to 1.
    for (double c : {0.1, 0.5, 1.3}) {
      Eigen::VectorXd rows = Eigen::VectorXd::Zero(f.size);
      for (std::size_t i = 0; i < f.offsets.size(); ++i) rows += f.block(i, c).rowwise().sum();
      BOOST_TEST((rows.array() - 1.0).abs().maxCoeff() < 1e-13);
    }
  }
}

// The closed-form 2 x 2 route (rank reduction) against a plain dense eigensolver on G.
BOOST_AUTO_TEST_CASE(reduced_spectral_radius_matches_dense_eigenvalues) {
  const CellLayout layout{{0.05, 0.3, 0.62, 0.9}, {2, 1, 1, 3}};
  for (auto s : kSchemes)
    for (auto m : kModels) {
      const OneStepMap map = build_one_step_map(layout, s, m);
      L2Criterion l2(map);
      for (double c : {0.2, 0.65, 1.1})
        for (double theta : {0.0, 0.01, 0.7, 2.0, std::numbers::pi}) {
          double dense = 0.0;
          for (const auto& f : map.families) {
            FamilySpectrum spectrum(f);
            BOOST_TEST(spectrum.reduced_size() == 2);
            const Eigen::MatrixXcd g = amplification_matrix(f, c, theta);
            dense = std::max(dense, Eigen::ComplexEigenSolver<Eigen::MatrixXcd>(g, false)
                                        .eigenvalues()
                                        .cwiseAbs()
                                        .maxCoeff());
          }
          BOOST_TEST(std::abs(l2.spectral_radius(c, theta) - dense) < 1e-12);
        }
    }
}

BOOST_AUTO_TEST_CASE(limit_is_a_transition_of_the_criteria) {
  const CellLayout layout{{0.6083, 0.955}, {}};
  for (auto s : kSchemes) {
    const OneStepMap map = build_one_step_map(layout, s, Model::elastic);
    L2Criterion l2(map);
    const CourantResult r =
        admissible_courant(map, Criterion::l2, default_search_options(Criterion::l2));
    BOOST_TEST(r.failing_courant - r.courant <= 1e-6);
    // Below: every theta passes; just above (1e-4): some rho exceeds 1.
    for (double c : {0.25 * r.courant, 0.5 * r.courant, r.courant - 1e-4}) {
      double worst = 0.0;
      for (int k = 0; k <= 2000; ++k)
        worst = std::max(worst, l2.spectral_radius(c, std::numbers::pi * k / 2000));
      BOOST_TEST(worst <= 1.0 + 1e-12);
    }
    BOOST_TEST(l2.margin(r.courant + 1e-4).value > 0.0);
    const CourantResult mono =
        admissible_courant(map, Criterion::monotone, default_search_options(Criterion::monotone));
    BOOST_TEST(monotone_margin(map, mono.courant - 1e-4).value <= 1e-12);
    BOOST_TEST(monotone_margin(map, mono.courant + 1e-4).value > 1e-8);
    BOOST_TEST(mono.limiting_particle >= 0);
    BOOST_TEST(mono.courant <= r.courant);  // monotone is sufficient for L2
  }
}

BOOST_AUTO_TEST_CASE(layout_validation) {
  auto fails = [](const CellLayout& l, const std::string& what) {
    try {
      validate(l);
    } catch (const std::invalid_argument& e) {
      return std::string(e.what()).find(what) != std::string::npos;
    }
    return false;
  };
  BOOST_TEST(fails({{}, {}}, "no particle"));
  BOOST_TEST(fails({{0.5, 1.2}, {}}, "position 2 (1.2) is outside the cell"));
  BOOST_TEST(fails({{-0.1}, {}}, "outside the cell"));
  BOOST_TEST(fails({{std::nan("")}, {}}, "outside the cell"));
  BOOST_TEST(fails({{0.2, 0.4}, {1.0}}, "1 masses for 2 positions"));
  BOOST_TEST(fails({{0.2, 0.4}, {1.0, 0.0}}, "mass 2 (0) must be positive"));
  BOOST_TEST(fails({{0.2}, {-1.0}}, "must be positive"));
  BOOST_CHECK_NO_THROW(validate({{0.0, 1.0}, {1.0, 2.0}}));
  BOOST_CHECK_THROW(build_one_step_map({{2.0}, {}}, TimeScheme::euler, Model::elastic),
                    std::invalid_argument);
  const CellLayout m = mirror({{0.25, 0.9}, {1.0, 3.0}});
  BOOST_TEST((m.positions == std::vector<double>{0.75, 1.0 - 0.9}));
  BOOST_TEST((m.masses == std::vector<double>{1.0, 3.0}));
}
