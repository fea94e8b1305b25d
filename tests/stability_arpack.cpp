// ARPACK reverse communication (stability/arpack_spectrum.hpp): on known operators, then the
// whole-grid operator of lib's step against the von Neumann analysis.
#define BOOST_TEST_MODULE stability_arpack
#include <boost/test/unit_test.hpp>

#include "stability/admissible_courant.hpp"
#include "stability/arpack_spectrum.hpp"
#include "stability/periodic_spectrum.hpp"
#include "stability/step_operator.hpp"

#include <dgmpm/physics/elastic_bar.hpp>
#include <dgmpm/time_integration.hpp>

#include <cmath>
#include <complex>
#include <numbers>

using namespace dgmpm::stability;

// Periodic upwind u_j -= c (u_j - u_{j-1}): eigenvalues 1 - c + c e^{-2 pi i k / n}, known by hand.
BOOST_AUTO_TEST_CASE(circulant_upwind_eigenvalues) {
  const int n = 40;  // eigenvalues on a circle: a few distinct moduli near the top
  const double c = 1.4;
  const auto apply = [&](const double* x, double* y) {
    for (int j = 0; j < n; ++j) y[j] = (1.0 - c) * x[j] + c * x[(j + n - 1) % n];
  };
  const auto values = largest_magnitude_eigenvalues(n, apply);
  BOOST_TEST_REQUIRE(values.size() >= 6u);  // nev + 1 when a conjugate pair straddles
  const double expected = 2.0 * c - 1.0;    // k = n / 2: 1 - 2c
  BOOST_TEST(std::abs(std::abs(values[0]) - expected) < 1e-10);
  BOOST_TEST(std::abs(values[0].real() - (1.0 - 2.0 * c)) < 1e-10);
  for (std::size_t k = 1; k < values.size(); ++k)
    BOOST_TEST(std::abs(values[k]) <= std::abs(values[k - 1]) + 1e-14);
}

BOOST_AUTO_TEST_CASE(small_operator_falls_back_to_dense) {
  const auto apply = [](const double* x, double* y) {
    y[0] = 2.0 * x[0] + x[1];
    y[1] = -x[0] + 2.0 * x[1];
    y[2] = 0.5 * x[2];
  };
  const auto values = largest_magnitude_eigenvalues(3, apply);  // 2 +- i, 0.5
  BOOST_TEST(std::abs(std::abs(values[0]) - std::sqrt(5.0)) < 1e-14);
  BOOST_TEST(std::abs(spectral_radius(3, apply) - std::sqrt(5.0)) < 1e-14);
}

// The global one-step operator of E periodic cells holding a layout has the eigenvalues of
// G(theta_k), theta_k = 2 pi k / E: ARPACK's spectral radius must equal the von Neumann one.
BOOST_AUTO_TEST_CASE(global_operator_matches_von_neumann) {
  struct Case {
    CellLayout layout;
    TimeScheme scheme;
    Model model;
    int cells;
  };
  const Case cases[] = {
      {regular_layout(2), TimeScheme::euler, Model::advection, 24},
      {{{0.6083, 0.955}, {}}, TimeScheme::euler, Model::elastic, 20},
      {{{0.1, 0.45, 0.8}, {1, 2, 1}}, TimeScheme::rk2, Model::advection, 16},
      {{{0.05, 0.3, 0.55, 0.9}, {1, 2, 1, 1.5}}, TimeScheme::rk2, Model::elastic, 12},
  };
  for (const Case& k : cases) {
    const OneStepMap map = build_one_step_map(k.layout, k.scheme, k.model);
    const double limit =
        admissible_courant(map, Criterion::l2, default_search_options(Criterion::l2)).courant;
    for (double c : {0.5 * limit, 1.1 * limit, 1.3 * limit}) {
      BOOST_TEST_CONTEXT(describe(k.layout.positions) << ", " << to_string(k.scheme) << ", "
                                                      << to_string(k.model) << ", C = " << c) {
        const double arpack =
            periodic_grid_spectral_radius(k.layout, k.scheme, k.model, k.cells, c);
        const double von_neumann = discrete_von_neumann_radius(map, k.cells, c);
        BOOST_TEST(std::abs(arpack - von_neumann) < 1e-8, arpack << " vs " << von_neumann);
        BOOST_TEST_MESSAGE("ARPACK " << arpack << ", von Neumann " << von_neumann << ", difference "
                                     << arpack - von_neumann);
      }
    }
  }
}

// The search routine works on any spectral radius function: here the global ARPACK one, whose
// first failing C on a 12-cell grid cannot be below the von Neumann limit (all theta).
BOOST_AUTO_TEST_CASE(search_over_arpack_spectral_radius) {
  const CellLayout layout = regular_layout(2);
  const int cells = 12;
  SearchOptions options;
  options.scan_step = 0.05;
  options.max_courant = 2.0;
  options.courant_tolerance = 1e-6;
  options.margin_tolerance = 1e-9;
  const SearchResult r = search_admissible_courant(
      [&](double c) {
        return periodic_grid_spectral_radius(layout, TimeScheme::euler, Model::advection, cells,
                                             c) -
               1.0;
      },
      options);
  const OneStepMap map = build_one_step_map(layout, TimeScheme::euler, Model::advection);
  const double local =
      admissible_courant(map, Criterion::l2, default_search_options(Criterion::l2)).courant;
  BOOST_TEST(r.bounded);
  BOOST_TEST(r.courant >= local - 1e-6);
  // Same transition seen through the discrete von Neumann radius.
  const SearchResult d = search_admissible_courant(
      [&](double c) { return discrete_von_neumann_radius(map, cells, c) - 1.0; }, options);
  BOOST_TEST(std::abs(r.courant - d.courant) < 1e-5, r.courant << " vs " << d.courant);
}

// A spectral radius is 1 up to C* and rises after it (a margin flat below the limit): bisection
// finds the same bracket as Brent's refinement without its minimal steps off the passing end
// (each an ARPACK eigenproblem in `dgmpm courant --scene`), so in fewer evaluations.
BOOST_AUTO_TEST_CASE(bisection_refines_a_flat_margin_in_fewer_evaluations) {
  const double limit = 0.7310441;
  const auto radius_minus_one = [&](double c) { return c <= limit ? 0.0 : 0.4 * (c - limit); };
  SearchOptions options;
  options.scan_step = 0.24;
  options.max_courant = 2.0;
  options.courant_tolerance = 5e-3;
  options.significant_digits = 3;
  options.margin_tolerance = 1e-9;
  const SearchResult brent = search_admissible_courant(radius_minus_one, options);
  options.bisect = true;
  const SearchResult bisection = search_admissible_courant(radius_minus_one, options);
  BOOST_TEST_MESSAGE("evaluations: Brent " << brent.evaluations << ", bisection "
                                           << bisection.evaluations);
  for (const SearchResult& r : {brent, bisection}) {
    BOOST_TEST(r.courant <= limit);
    BOOST_TEST(r.courant >= limit - 5e-3);
    BOOST_TEST(r.failing_courant > limit);
    BOOST_TEST(r.failing_courant - r.courant <= 5e-3 + 1e-3);  // the bracket, and the rounding
  }
  BOOST_TEST(bisection.evaluations < brent.evaluations);
}

// What `dgmpm courant --scene` builds on: step_operator wraps any lib operator and integrator
// (here a bar with reflecting ends, not periodic) and the search runs on its ARPACK radius.
BOOST_AUTO_TEST_CASE(step_operator_on_a_bar_with_reflecting_ends) {
  using namespace dgmpm;
  const int cells = 30;
  Grid<1> grid;
  grid.cells = {cells};
  Particles<1, 2> particles;
  particles.resize(cells);
  for (int p = 0; p < cells; ++p) {
    particles.position(0, p) = p + 0.5;
    particles.mass[p] = particles.volume[p] = 1.0;
    particles.material[p] = 0;
    particles.id[p] = p;
  }
  const std::vector<ElasticBar::Material> materials{{1.0, 1.0}};
  Boundaries<1> free_ends{};  // free: sigma = 0, homogeneous
  Stepper<ElasticBar> euler(grid, free_ends, StepperOptions{TimeScheme::euler});
  euler.rebuild(particles, materials);
  const int n = 2 * cells;
  const auto radius = [&](double courant) {
    return spectral_radius(n, step_operator(euler, particles.mass, courant));
  };
  // A rigid translation (v uniform, sigma = 0) is kept exactly: eigenvalue 1.
  BOOST_TEST(std::abs(radius(0.5) - 1.0) < 1e-9);
  BOOST_TEST(std::abs(radius(1.2) - 1.4) < 1e-9);  // 1 - 2C at theta = pi, as upwind

  // Powers of the operator separate the moduli; the radius is the same.
  ArpackOptions powers;
  powers.steps_per_product = 10;
  for (double c : {0.5, 0.9, 1.2})
    BOOST_TEST(std::abs(spectral_radius(n, step_operator(euler, particles.mass, c), powers) -
                        radius(c)) < 1e-9);
  // ARPACK stopped early: dense fallback when allowed, a clear error otherwise.
  ArpackOptions starved;
  starved.eigenvalues = 2;
  starved.basis_size = 6;
  starved.max_restarts = 1;
  const auto op_09 = step_operator(euler, particles.mass, 0.9);
  BOOST_TEST(std::abs(spectral_radius(n, op_09, starved) - 1.0) < 1e-9);
  starved.dense_limit = 0;
  BOOST_CHECK_THROW(spectral_radius(n, op_09, starved), std::runtime_error);
  SearchOptions options;
  options.scan_step = 0.1;
  options.max_courant = 2.0;
  options.courant_tolerance = 1e-6;
  options.margin_tolerance = 1e-9;
  const SearchResult r =
      search_admissible_courant([&](double c) { return radius(c) - 1.0; }, options);
  BOOST_TEST(r.bounded);
  BOOST_TEST(std::abs(r.courant - 1.0) < 1e-5, "C* = " << r.courant);
}
