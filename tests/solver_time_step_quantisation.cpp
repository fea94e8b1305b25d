// Automatic time step: the error that the cache's rounding of positions brings to C*.
//
// TimeStepControl analyses each cell's layout with its local positions rounded by
// LayoutQuantisation::quantise_position: to q = 1/4096 (moving particles), except near a node,
// where the distance d to the node keeps 8 significant bits, so a particle moves by delta <= min(q
// / 2, d / 512); below d = q / 2 it is put on the node. This file measures e = |C*(rounded layout)
// - C*(exact layout)| / C*(exact layout) against delta / g, g being the smallest gap of the exact
// layout (particle to node, particle to particle).
//
// Measured on random 2-4 particle layouts (seed 7: 6000 for l2, 36000 for monotone; 40 % of the
// positions within 0.05 of a node, down to sub-quantum distances; masses equal or in [0.5, 2]):
//
//   e <= A delta / g, largest A seen:  euler/l2 0.98   euler/monotone 1.49
//                                      rk2/l2   1.84   rk2/monotone   10.8
//   worst e over all layouts:          euler/l2 2.2e-3 euler/monotone 2.5e-3
//                                      rk2/l2   7.2e-3 rk2/monotone   0.106 (two particles
//                                      0.2 q apart, 0.003 from a node)
//   worst e when every gap >= 1/16:    8.5e-4, 1.8e-3, 7.3e-4, 2.3e-3
//
// The tests assert about twice these on the first 2000 (l2) or 12000 (monotone) layouts (whose
// worst A is lower: 0.69, 1.12, 1.84, 3.43).

#define BOOST_TEST_MODULE time_step_quantisation
#include <boost/test/unit_test.hpp>

#include "solver/time_step_control.hpp"

#include <stability/admissible_courant.hpp>

#include <algorithm>
#include <cmath>
#include <random>
#include <utility>
#include <vector>

using namespace dgmpm;
using stability::CellLayout;
using stability::Criterion;
using stability::TimeScheme;

namespace {

constexpr double q = LayoutQuantisation::moving_position_quantum;

double courant(const CellLayout& layout, TimeScheme scheme, Criterion criterion) {
  return stability::admissible_courant(layout, scheme, criterion, stability::Model::elastic)
      .courant;
}

// The layout the cache analyses (as LayoutQuantisation::fill_key builds it): positions through
// LayoutQuantisation::quantise_position, sorted, masses relative to the first particle's.
CellLayout quantised(const CellLayout& layout) {
  std::vector<std::pair<double, double>> entries;
  for (int k = 0; k < layout.size(); ++k)
    entries.emplace_back(LayoutQuantisation::quantise_position(layout.positions[k], q),
                         layout.weight(k));
  std::sort(entries.begin(), entries.end());
  CellLayout r;
  for (const auto& e : entries) r.positions.push_back(e.first);
  for (const auto& e : entries) r.masses.push_back(e.second / entries.front().second);
  return r;
}

// C*(rounded) / C*(exact).
double overestimate(const CellLayout& exact, TimeScheme scheme, Criterion criterion) {
  return courant(quantised(exact), scheme, criterion) / courant(exact, scheme, criterion);
}

// Smallest distance of a particle to a node or to another particle.
double smallest_gap(const CellLayout& layout) {
  double g = 1.0;
  for (int a = 0; a < layout.size(); ++a) {
    const double x = layout.positions[a];
    g = std::min({g, x, 1.0 - x});
    for (int b = a + 1; b < layout.size(); ++b) g = std::min(g, std::abs(x - layout.positions[b]));
  }
  return g;
}

// Random layouts of 2 to 4 particles: each on the quantum grid, 40 % of them within 0.05 of a
// node (distance log-uniform in [q, 0.05]), then moved by up to q/2 (every other layout by
// +-0.4999 q, the worst case); masses equal or relative weights in [0.5, 2].
class LayoutGenerator {
 public:
  CellLayout next() {
    const int n = 2 + count_++ % 3;
    const bool extreme = count_ % 2 == 0;
    CellLayout layout;
    for (int k = 0; k < n; ++k) {
      double x = u_(rng_);
      if (u_(rng_) < 0.4) {
        const double d = std::exp(std::log(q) + u_(rng_) * (std::log(0.05) - std::log(q)));
        x = u_(rng_) < 0.5 ? d : 1.0 - d;
      }
      x = std::round(x / q) * q;
      const double shift = extreme ? (u_(rng_) < 0.5 ? -0.4999 : 0.4999) * q : (u_(rng_) - 0.5) * q;
      layout.positions.push_back(std::clamp(x + shift, 0.0, 1.0));
      layout.masses.push_back(u_(rng_) < 0.5 ? 1.0 : 0.5 + 1.5 * u_(rng_));
    }
    return layout;
  }

 private:
  std::mt19937 rng_{7};
  std::uniform_real_distribution<double> u_{0.0, 1.0};
  int count_ = 0;
};

// Largest distance the rounding moves a particle of the layout.
double rounding_shift(const CellLayout& layout) {
  double shift = 0.0;
  for (double x : layout.positions)
    shift = std::max(shift, std::abs(LayoutQuantisation::quantise_position(x, q) - x));
  return shift;
}

// Checks e <= a delta / g (delta: rounding_shift, g: smallest_gap) on `samples` generated layouts
// (all but those with a particle put on a node, closer than q / 2 to it), and e <= interior when
// every gap is at least 1/16 of a cell; reports the worst values seen.
void check_quantisation_error(TimeScheme scheme, Criterion criterion, int samples, double a,
                              double interior) {
  LayoutGenerator generator;
  double worst_a = 0, worst = 0, worst_interior = 0;
  int near = 0;
  for (int i = 0; i < samples; ++i) {
    const CellLayout exact = generator.next();
    const auto on_node = [](double x) { return std::min(x, 1.0 - x) < 0.5 * q; };
    if (std::any_of(exact.positions.begin(), exact.positions.end(), on_node)) continue;
    const double g = smallest_gap(exact), delta = rounding_shift(exact);
    const double c_exact = courant(exact, scheme, criterion);
    const double e = std::abs(courant(quantised(exact), scheme, criterion) - c_exact) / c_exact;
    BOOST_TEST_CONTEXT("layout " << stability::describe(exact.positions) << ", masses "
                                 << stability::describe(exact.masses) << ", g = " << g / q
                                 << " q") {
      BOOST_TEST(e * g <= a * delta);
      if (g >= 1.0 / 16) BOOST_TEST(e <= interior);
    }
    if (delta > 0) worst_a = std::max(worst_a, e * g / delta);
    worst = std::max(worst, e);
    if (g >= 1.0 / 16) worst_interior = std::max(worst_interior, e);
    if (g < 4 * q) ++near;
  }
  BOOST_TEST_MESSAGE(stability::to_string(scheme)
                     << "/" << stability::to_string(criterion) << ": worst e g / delta " << worst_a
                     << ", worst e " << worst << ", worst e with g >= 1/16 " << worst_interior
                     << "; " << near << " layouts with g < 4 q");
  BOOST_TEST(near >= samples / 50);  // the sample reaches the near-node regime
  BOOST_TEST(worst_a > a / 8);       // and the bound is not loose enough to pass anything
}

}  // namespace

// One particle: C* = 1 wherever it sits, rounded or not (even when rounded onto a node), to the
// 7 significant digits C* is given in (rounded down where round-off reaches the tolerance at 1).
BOOST_AUTO_TEST_CASE(one_particle_layouts_lose_nothing) {
  std::vector<double> xs;
  for (int j = 0; j < 20; ++j) xs.push_back((j + 0.3712) / 20);
  for (double f : {0.3, 0.49, 0.51, 1.3, 2.5, 10.5}) {
    xs.push_back(f * q);
    xs.push_back(1.0 - f * q);
  }
  for (auto scheme : {TimeScheme::euler, TimeScheme::rk2})
    for (auto criterion : {Criterion::l2, Criterion::monotone})
      for (double x : xs)
        BOOST_TEST_CONTEXT(stability::to_string(scheme)
                           << "/" << stability::to_string(criterion) << ", xi = " << x) {
          const CellLayout exact{{x}, {}};
          BOOST_TEST(courant(exact, scheme, criterion) == 1.0, boost::test_tools::tolerance(2e-7));
          BOOST_TEST(courant(exact, scheme, criterion) <= 1.0);
          BOOST_TEST(courant(quantised(exact), scheme, criterion) == 1.0,
                     boost::test_tools::tolerance(2e-7));
        }
}

BOOST_AUTO_TEST_CASE(rounding_moves_a_particle_by_at_most_its_bound) {
  std::mt19937 rng(11);
  std::uniform_real_distribution<double> u(0.0, 1.0);
  for (int i = 0; i < 100000; ++i) {
    // Log-uniform distances to a node from 1e-15 to 1/2.
    const double d = std::exp(std::log(1e-15) + u(rng) * (std::log(0.5) - std::log(1e-15)));
    const double x = u(rng) < 0.5 ? d : 1.0 - d;
    for (double quantum : {q, LayoutQuantisation::fixed_position_quantum}) {
      const double r = LayoutQuantisation::quantise_position(x, quantum);
      const double dist = std::min(x, 1.0 - x);
      if (dist < 0.5 * quantum) {
        BOOST_TEST(r == (x < 0.5 ? 0.0 : 1.0));
        continue;
      }
      BOOST_TEST(std::abs(r - x) <= std::min(0.5 * quantum, dist / 512) * (1 + 1e-12) + 1e-17);
      BOOST_TEST((r > 0.0 && r < 1.0));
    }
  }
  BOOST_TEST(LayoutQuantisation::quantise_position(0.0, q) == 0.0);
  BOOST_TEST(LayoutQuantisation::quantise_position(1.0, q) == 1.0);
  // Away from the nodes the cache's quantum rules: 1000 + 1/3 quanta round to 1000 quanta.
  BOOST_TEST(LayoutQuantisation::quantise_position((1000 + 1.0 / 3) * q, q) == 1000 * q);
}

// Bounds: about twice the worst seen in the measurements described at the top of the file.
BOOST_AUTO_TEST_CASE(euler_l2_error_is_below_2_delta_over_the_smallest_gap) {
  check_quantisation_error(TimeScheme::euler, Criterion::l2, 2000, 2.0, 2e-3);
}

BOOST_AUTO_TEST_CASE(euler_monotone_error_is_below_3_delta_over_the_smallest_gap) {
  check_quantisation_error(TimeScheme::euler, Criterion::monotone, 12000, 3.0, 4e-3);
}

BOOST_AUTO_TEST_CASE(rk2_l2_error_is_below_4_delta_over_the_smallest_gap) {
  check_quantisation_error(TimeScheme::rk2, Criterion::l2, 2000, 4.0, 2e-3);
}

BOOST_AUTO_TEST_CASE(rk2_monotone_error_is_below_22_delta_over_the_smallest_gap) {
  check_quantisation_error(TimeScheme::rk2, Criterion::monotone, 12000, 22.0, 5e-3);
}

// The measurement quoted at the top of the file (15 s; not run by default):
//   build/bin/test_solver_time_step_quantisation --log_level=message
//       --run_test=measure_on_the_large_sample
BOOST_AUTO_TEST_CASE(measure_on_the_large_sample, *boost::unit_test::disabled()) {
  check_quantisation_error(TimeScheme::euler, Criterion::l2, 6000, 2.0, 2e-3);
  check_quantisation_error(TimeScheme::euler, Criterion::monotone, 36000, 3.0, 4e-3);
  check_quantisation_error(TimeScheme::rk2, Criterion::l2, 6000, 4.0, 2e-3);
  check_quantisation_error(TimeScheme::rk2, Criterion::monotone, 36000, 22.0, 5e-3);
}

// Documents the price of the resolution, not a requirement: a particle less than q/2 from a
// node is put on it. Below node 1 that makes it the next cell's xi = 0, so {0, 1 - d} is analysed
// as one particle (C* = 1) while C*(exact) -> 0 (like sqrt(d) for euler/l2, like d for monotone),
// and two particles near node 0 merge into {0, 0}. Moving particles pass through such layouts in
// a step or two; resolving them would make dt ~ d h / c (see time_step_control.hpp). Two
// particles near node 0 leave node 1 near-empty: under RK2 the consistent formulation damps its
// first stage, and their C* stays close to {0, 0}'s (it fell like d with the paper's form).
BOOST_AUTO_TEST_CASE(a_particle_put_onto_node_one_overestimates_without_bound) {
  for (double f : {0.45, 0.25, 0.0625}) {
    const double d = f * q;
    BOOST_TEST_CONTEXT("d = " << f << " q") {
      const CellLayout pair{{0.0, 1.0 - d}, {}};
      BOOST_TEST(overestimate(pair, TimeScheme::euler, Criterion::l2) > 90 / std::sqrt(f / 0.45));
      BOOST_TEST(overestimate(pair, TimeScheme::euler, Criterion::monotone) > 0.9 / d);
      BOOST_TEST(overestimate(pair, TimeScheme::rk2, Criterion::monotone) > 0.9 / d);
      BOOST_TEST(overestimate(pair, TimeScheme::rk2, Criterion::l2) == 1.0,
                 boost::test_tools::tolerance(0.02));  // continuous there
    }
  }
}

BOOST_AUTO_TEST_CASE(two_particles_put_onto_node_zero_overestimate_little) {
  for (double f : {0.45, 0.25, 0.0625}) {
    const double d = f * q;
    BOOST_TEST_CONTEXT("positions {" << f / 2 << " q, " << f << " q}") {
      const CellLayout pair{{d / 2, d}, {}};
      BOOST_TEST(overestimate(pair, TimeScheme::rk2, Criterion::l2) <= 1.2);        // measured 1.14
      BOOST_TEST(overestimate(pair, TimeScheme::rk2, Criterion::monotone) <= 1.5);  // 1.44
      BOOST_TEST(overestimate(pair, TimeScheme::euler, Criterion::l2) == 1.0,
                 boost::test_tools::tolerance(1e-4));
    }
  }
}

// From half a quantum on, relative rounding keeps such layouts apart and their C* close.
BOOST_AUTO_TEST_CASE(layouts_half_a_quantum_or_more_from_a_node_keep_their_courant_number) {
  for (double f : {0.5, 0.7, 2.0, 10.0})
    for (auto scheme : {TimeScheme::euler, TimeScheme::rk2})
      for (auto criterion : {Criterion::l2, Criterion::monotone}) {
        const double d = f * q;
        for (const CellLayout& exact :
             {CellLayout{{0.0, 1.0 - d}, {}}, CellLayout{{0.3, 1.0 - d}, {}},
              CellLayout{{d, 2 * d}, {}}}) {
          BOOST_TEST_CONTEXT(stability::to_string(scheme)
                             << "/" << stability::to_string(criterion) << ", layout "
                             << stability::describe(exact.positions)) {
            BOOST_TEST(std::abs(overestimate(exact, scheme, criterion) - 1.0) <= 0.01);
          }
        }
      }
}
