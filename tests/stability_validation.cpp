// Validation of the von Neumann predictions against lib's own stepping on a periodic grid:
// bounded below the L2 limit, growth rate of the most unstable Fourier
// mode above it, and no new extrema below the monotone limit.
#define BOOST_TEST_MODULE stability_validation
#include <boost/test/unit_test.hpp>

#include "stability/admissible_courant.hpp"
#include "stability/criteria.hpp"
#include "stability/periodic_cells.hpp"

#include <Eigen/Eigenvalues>
#include <cmath>
#include <complex>
#include <numbers>
#include <random>

using namespace dgmpm;
using namespace dgmpm::stability;
using Complex = std::complex<double>;

namespace {

std::vector<CellLayout> layouts() {
  return {regular_layout(1),
          regular_layout(2),
          regular_layout(3),
          regular_layout(4),
          {{0.3}, {}},
          {{0.2, 0.65}, {1.0, 2.0}},
          {{0.6083, 0.955}, {}},
          {{0.1, 0.45, 0.8}, {1.0, 2.0, 1.0}},
          {{0.05, 0.3, 0.55, 0.9}, {1.0, 2.0, 1.0, 1.5}}};
}

constexpr TimeScheme kSchemes[] = {TimeScheme::euler, TimeScheme::rk2};

double l2_limit(const OneStepMap& map) {
  return admissible_courant(map, Criterion::l2, default_search_options(Criterion::l2)).courant;
}

// Characteristic value w = q0 -+ q1 of a particle (elastic, unit material) or u (advection).
template <class Physics>
double family_value(const PeriodicCells<Physics>& grid, int p, const std::string& direction) {
  if constexpr (Physics::n_comp == 1) {
    return grid.state()(0, p);
  } else {
    const double s = direction == "+x" ? -1.0 : 1.0;
    return grid.state()(0, p) + s * grid.state()(1, p);
  }
}

// Sets the family's characteristic value of every particle (the other family's to zero).
template <class Physics>
void set_family_value(PeriodicCells<Physics>& grid, int p, const std::string& direction, double w) {
  if constexpr (Physics::n_comp == 1) {
    grid.state()(0, p) = w;
  } else {
    // w+ = q0 - q1, w- = q0 + q1 with the other characteristic zero.
    grid.state()(0, p) = 0.5 * w;
    grid.state()(1, p) = direction == "+x" ? -0.5 * w : 0.5 * w;
  }
}

// |u_hat(theta)|: Fourier coefficient over cells of the family's values.
template <class Physics>
double fourier_amplitude(const PeriodicCells<Physics>& grid, const std::string& direction,
                         double theta) {
  const int n = grid.particles_per_cell();
  double sum = 0.0;
  for (int i = 0; i < n; ++i) {
    Complex c = 0.0;
    for (int e = 0; e < grid.cells(); ++e)
      c += family_value(grid, e * n + i, direction) * std::polar(1.0, -theta * e);
    sum += std::norm(c);
  }
  return std::sqrt(sum);
}

template <class Physics>
void check_bounded_below_limit(const CellLayout& layout, TimeScheme scheme, double courant) {
  PeriodicCells<Physics> grid(layout, 16, AnalysisSetting{1, scheme});
  std::mt19937 rng(3);
  std::uniform_real_distribution<double> value(-1.0, 1.0);
  for (int p = 0; p < grid.num_particles(); ++p)
    for (int c = 0; c < Physics::n_comp; ++c) grid.state()(c, p) = value(rng);
  const double initial = grid.state().cwiseAbs().maxCoeff();
  double largest = initial;
  for (int step = 1; step <= 100000; ++step) {
    grid.step(courant);
    if (step % 1000 == 0) largest = std::max(largest, grid.state().cwiseAbs().maxCoeff());
  }
  BOOST_TEST(std::isfinite(largest));
  BOOST_TEST(largest <= 10.0 * initial, "max |q| grew from " << initial << " to " << largest);
}

// Above the limit: the grid's most unstable mode, started from its eigenvector, must grow per
// step as the predicted spectral radius.
template <class Physics>
void check_growth_above_limit(const CellLayout& layout, TimeScheme scheme, Model model) {
  constexpr int cells = 16;
  const OneStepMap map = build_one_step_map(layout, scheme, model);
  L2Criterion l2(map);
  const double limit = l2_limit(map);
  // Smallest C (step 0.002) where a wavenumber of the grid has rho >= 1 + 2e-3.
  double courant = limit, rho = 0.0, theta = 0.0;
  while (rho < 1.0 + 2e-3 && courant < limit + 1.0) {
    courant += 0.002;
    rho = 0.0;
    for (int k = 0; k <= cells / 2; ++k) {
      const double t = 2.0 * std::numbers::pi * k / cells;
      if (const double r = l2.spectral_radius(courant, t); r > rho) rho = r, theta = t;
    }
  }
  BOOST_TEST_REQUIRE(rho >= 1.0 + 1e-3);
  // The family and eigenvector carrying rho.
  const StencilFamily* family = nullptr;
  Eigen::VectorXcd mode;
  double best = 0.0;
  for (const auto& f : map.families) {
    Eigen::ComplexEigenSolver<Eigen::MatrixXcd> es(amplification_matrix(f, courant, theta));
    Eigen::Index k;
    const double r = es.eigenvalues().cwiseAbs().maxCoeff(&k);
    if (r > best) best = r, family = &f, mode = es.eigenvectors().col(k);
  }
  BOOST_TEST(std::abs(best - rho) < 1e-12);

  PeriodicCells<Physics> grid(layout, cells, AnalysisSetting{1, scheme});
  grid.state().setZero();
  const int n = layout.size();
  for (int e = 0; e < cells; ++e)
    for (int i = 0; i < n; ++i)
      set_family_value(grid, e * n + i, family->direction,
                       std::real(mode[i] * std::polar(1.0, theta * e)));
  for (int step = 0; step < 20; ++step) grid.step(courant);  // transients
  const double before = fourier_amplitude(grid, family->direction, theta);
  const int steps = std::min(50000, static_cast<int>(std::ceil(std::log(1e10) / std::log(rho))));
  for (int step = 0; step < steps; ++step) grid.step(courant);
  const double after = fourier_amplitude(grid, family->direction, theta);
  const double measured = std::pow(after / before, 1.0 / steps);
  BOOST_TEST_MESSAGE(to_string(model)
                     << " " << describe(layout.positions) << " " << to_string(scheme) << ": limit "
                     << limit << ", C = " << courant << ", theta = " << theta
                     << ", rho - 1 = " << rho - 1.0 << ", measured - 1 = " << measured - 1.0);

  BOOST_TEST(std::abs((measured - 1.0) - (rho - 1.0)) <= 0.05 * (rho - 1.0),
             "C = " << courant << " (limit " << limit << "), theta = " << theta
                    << ": measured growth " << measured << ", predicted rho " << rho);

  // From random data, no Fourier analysis: after the transients the whole solution grows at the
  // rate of the grid's most unstable mode.
  std::mt19937 rng(11);
  std::uniform_real_distribution<double> value(-1.0, 1.0);
  for (int p = 0; p < grid.num_particles(); ++p)
    for (int c = 0; c < Physics::n_comp; ++c) grid.state()(c, p) = value(rng);
  const int transient = static_cast<int>(std::ceil(std::log(1e8) / std::log(rho)));
  for (int step = 0; step < transient; ++step) grid.step(courant);
  const double start = grid.state().norm();
  for (int step = 0; step < steps; ++step) grid.step(courant);
  const double random_growth = std::pow(grid.state().norm() / start, 1.0 / steps);
  BOOST_TEST(std::abs((random_growth - 1.0) - (rho - 1.0)) <= 0.05 * (rho - 1.0),
             "random start: measured growth " << random_growth << ", predicted rho " << rho);
  BOOST_TEST_MESSAGE("  random start: measured - 1 = " << random_growth - 1.0);
}

// Square wave (1 on `width` consecutive particles from `first`, 0 elsewhere) advected by lib's
// step: does it stay inside its initial [0, 1] for 300 steps?
bool square_wave_stays_in_range(const CellLayout& layout, TimeScheme scheme, double courant,
                                int first, int width) {
  PeriodicCells<Advection<1>> grid(layout, 20, AnalysisSetting{1, scheme});
  for (int p = 0; p < grid.num_particles(); ++p)
    grid.state()(0, p) = p >= first && p < first + width ? 1.0 : 0.0;
  for (int step = 0; step < 300; ++step) {
    grid.step(courant);
    if (grid.state().minCoeff() < -1e-12 || grid.state().maxCoeff() > 1.0 + 1e-12) return false;
  }
  return true;
}

// The monotone criterion bounds arbitrary data, so the waves start at every phase in a cell:
// wide (half the grid), or narrow enough to resolve a single negative weight of the map.
int square_waves_leaving_range(const CellLayout& layout, TimeScheme scheme, double courant) {
  const int n = layout.size();
  int leaving = 0;
  for (int first = 0; first < n; ++first)
    for (int width : {1, 2, 3, n, 10 * n})
      leaving += !square_wave_stays_in_range(layout, scheme, courant, first + 4 * n, width);
  return leaving;
}

}  // namespace

BOOST_AUTO_TEST_CASE(bounded_just_below_the_l2_limit) {
  for (const auto& layout : layouts())
    for (auto scheme : kSchemes) {
      const double limit = l2_limit(build_one_step_map(layout, scheme, Model::advection));
      BOOST_TEST_CONTEXT(describe(layout.positions)
                         << ", " << to_string(scheme) << ", C = " << limit - 1e-3) {
        check_bounded_below_limit<Advection<1>>(layout, scheme, limit - 1e-3);
      }
    }
  // The elastic bar, both directions, on the asymmetric layout.
  const CellLayout asymmetric{{0.6083, 0.955}, {}};
  for (auto scheme : kSchemes) {
    const double limit = l2_limit(build_one_step_map(asymmetric, scheme, Model::elastic));
    check_bounded_below_limit<ElasticBar>(asymmetric, scheme, limit - 1e-3);
  }
}

BOOST_AUTO_TEST_CASE(growth_above_the_l2_limit_matches_the_spectral_radius) {
  for (const auto& layout : layouts())
    for (auto scheme : kSchemes) {
      BOOST_TEST_CONTEXT(describe(layout.positions) << ", " << to_string(scheme)) {
        check_growth_above_limit<Advection<1>>(layout, scheme, Model::advection);
      }
    }
  for (const auto& layout :
       {CellLayout{{0.6083, 0.955}, {}}, CellLayout{{0.1, 0.45, 0.8}, {1, 2, 1}}})
    for (auto scheme : kSchemes) {
      BOOST_TEST_CONTEXT("elastic, " << describe(layout.positions) << ", " << to_string(scheme)) {
        check_growth_above_limit<ElasticBar>(layout, scheme, Model::elastic);
      }
    }
}

BOOST_AUTO_TEST_CASE(square_wave_keeps_its_range_only_below_the_monotone_limit) {
  for (const auto& layout : layouts())
    for (auto scheme : kSchemes) {
      const double limit =
          admissible_courant(layout, scheme, Criterion::monotone, Model::advection).courant;
      BOOST_TEST_CONTEXT(describe(layout.positions)
                         << ", " << to_string(scheme) << ", limit " << limit) {
        BOOST_TEST(square_waves_leaving_range(layout, scheme, 0.99 * limit) == 0);
        BOOST_TEST(square_waves_leaving_range(layout, scheme, 1.05 * limit) > 0);
      }
    }
}
