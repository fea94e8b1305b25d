// The 2D von Neumann analysis (stability/ on lib's 2D stepper): the published limits, the 1D
// limits recovered when the problem is 1D, symmetries, the weak long-wave instability of RK2 with
// an off-centre particle, and validation by stepping the solver's operators.
#define BOOST_TEST_MODULE stability_two_dimensions
#include <boost/test/unit_test.hpp>

#include "common/analysis_settings.hpp"
#include "stability/admissible_courant.hpp"
#include "stability/criteria.hpp"
#include "stability/periodic_cells.hpp"

#include <algorithm>
#include <cmath>
#include <numbers>
#include <omp.h>
#include <random>

using namespace dgmpm;
using namespace dgmpm::stability;
using namespace dgmpm::test;

namespace {

double limit(const CellLayout& layout, const AnalysisSetting& s,
             Criterion criterion = Criterion::l2) {
  return admissible_courant(layout, s, criterion).courant;
}

}  // namespace

// docs/method.md, "Stability": values from two independent computations and the thesis.
BOOST_AUTO_TEST_CASE(published_values) {
  const CellLayout centre = points({0.5, 0.5});
  // The published values to the digits given (absolute 2e-3; 0.58 is given to 2 digits).
  const auto near = [](double computed, double published, double within = 2e-3) {
    return std::abs(computed - published) <= within;
  };
  BOOST_TEST(near(limit(centre, advection(1, 1, dcu, euler)), 0.5));
  BOOST_TEST(near(limit(centre, advection(1, 1, ctu, euler)), 1.0));
  BOOST_TEST(near(limit(centre, advection(1, 1, dcu, rk2)), 1.0));
  // Thesis, monotone, a = b, Euler.
  const CellLayout two = points({0.25, 0.5, 0.75, 0.5}), four = regular_layout(2, 2);
  BOOST_TEST(near(limit(two, advection(1, 1, dcu, euler), Criterion::monotone), 0.273));
  BOOST_TEST(near(limit(four, advection(1, 1, dcu, euler), Criterion::monotone), 0.167));
  BOOST_TEST(near(limit(four, advection(1, 1, ctu, euler), Criterion::monotone), 0.169));
  // Plane strain, one particle at the centre.
  BOOST_TEST(near(limit(centre, elastic(0.0, dcu, euler)), 0.58, 0.006));
  BOOST_TEST(near(limit(centre, elastic(0.3, dcu, euler)), 0.65));
  BOOST_TEST(near(limit(centre, elastic(0.45, dcu, euler)), 0.55));
  BOOST_TEST(near(limit(centre, elastic(0.3, ctu, euler)), 1.0));
  BOOST_TEST(near(limit(centre, elastic(0.3, dcu, rk2)), 1.0));
  // DCU's one-particle condition a dt/dx + b dt/dy <= 1 for other speeds.
  BOOST_TEST(limit(centre, advection(1, 0.4, dcu, euler)) == 1 / 1.4,
             boost::test_tools::tolerance(1e-6));
}

// Limits that are exact in exact arithmetic come back exact, not as the 1 + 1e-7 that the
// margin's round-off tolerance lets pass (a time step that much above 1 makes the energy grow);
// others are never above the true value, and within a few units of the 7th digit below it.
BOOST_AUTO_TEST_CASE(exact_limits_come_back_exact) {
  const CellLayout centre = points({0.5, 0.5});
  BOOST_TEST(limit(centre, elastic(0.3, dcu, rk2)) == 1.0);
  BOOST_TEST(limit(centre, elastic(0.3, ctu, euler)) == 1.0);
  BOOST_TEST(limit(centre, advection(1, 1, dcu, euler)) == 0.5);
  BOOST_TEST(limit(regular_layout(2, 2), elastic(0.3, dcu, rk2)) == 1.0);
  const double c = limit(centre, advection(1, 0.4, dcu, euler));
  BOOST_TEST(c <= 1 / 1.4);
  BOOST_TEST(c >= 1 / 1.4 - 3e-7);
  // 1D, one particle anywhere: exactly 1.
  for (double x : {0.5, 0.3712, 0.01856})
    BOOST_TEST(admissible_courant(CellLayout{{x}, {}}, TimeScheme::euler, Criterion::l2).courant ==
               1.0);
}

// b = 0 and a layout that repeats along y: the 1D problem, with the 1D L2 limit of the x
// positions. The monotone criterion needs a single row of particles: with two rows, the map
// mixes them with different weights in its identity and operator parts, and its row sums of
// |D| differ from the 1D ones. A single row off the cell's y centre gives the 1D value with
// Euler; with RK2 under the consistent formulation, within 1% of it (the row's top and bottom
// nodes carry different masses and each receives half an edge's flux, so they drift apart in the
// first stage: 0.943 against 0.940). With the paper's formulation, RK2 is not
// monotone there at any C: the row's top and bottom nodes carry different masses, the volume
// term does not cancel the fluxes of a constant state at each of them, the first stage leaves
// them different and the second stage's edge average mixes them: negative weights of order C^2
// where the first-order map has none.
BOOST_AUTO_TEST_CASE(one_dimensional_problems_give_the_1d_limits) {
  for (TimeScheme time : {euler, rk2})
    for (FluxScheme flux : {dcu, ctu}) {
      BOOST_TEST_CONTEXT(to_string(time) << ", " << to_string(flux)) {
        const double one_d =
            admissible_courant(CellLayout{{0.2, 0.7}, {}}, time, Criterion::l2, Model::advection)
                .courant;
        const CellLayout repeated = points({0.2, 0.25, 0.7, 0.25, 0.2, 0.75, 0.7, 0.75});
        BOOST_TEST(limit(repeated, advection(1, 0, flux, time)) == one_d,
                   boost::test_tools::tolerance(1e-6));
        const double mono_1d = admissible_courant(CellLayout{{0.2, 0.7}, {}}, time,
                                                  Criterion::monotone, Model::advection)
                                   .courant;
        BOOST_TEST(limit(points({0.2, 0.5, 0.7, 0.5}), advection(1, 0, flux, time),
                         Criterion::monotone) == mono_1d,
                   boost::test_tools::tolerance(1e-6));
        const CellLayout off_centre_row = points({0.2, 0.4, 0.7, 0.4});
        const double row = limit(off_centre_row, advection(1, 0, flux, time), Criterion::monotone);
        if (time == euler) {
          BOOST_TEST(row == mono_1d, boost::test_tools::tolerance(1e-6));
        } else {  // the face nodes still hold different masses: 0.943 against 0.940
          BOOST_TEST(row == mono_1d, boost::test_tools::tolerance(0.01));
        }
        const double paper_row =
            limit(off_centre_row, paper(advection(1, 0, flux, time)), Criterion::monotone);
        if (time == euler)
          BOOST_TEST(paper_row == mono_1d, boost::test_tools::tolerance(1e-6));
        else
          BOOST_TEST(paper_row < 1e-3);
      }
    }
}

// Swapping x and y (positions, speeds, aspect) leaves C* unchanged; so does mirroring a layout
// along x with the x speed reversed.
BOOST_AUTO_TEST_CASE(symmetries) {
  const CellLayout layout = points({0.3, 0.6, 0.8, 0.25}, {1.0, 2.0});
  for (TimeScheme time : {euler, rk2})
    for (FluxScheme flux : {dcu, ctu}) {
      BOOST_TEST_CONTEXT(to_string(time) << ", " << to_string(flux)) {
        AnalysisSetting a = advection(1.0, 0.6, flux, time), b = advection(0.6, 1.0, flux, time);
        a.aspect = 1.5;
        b.aspect = 1 / 1.5;
        const double c = limit(layout, a);
        BOOST_TEST(limit(transpose(layout), b) == c, boost::test_tools::tolerance(1e-6));
        AnalysisSetting reversed = a;
        reversed.speed_x = -a.speed_x;
        BOOST_TEST(limit(mirror(layout), reversed) == c, boost::test_tools::tolerance(1e-6));
        AnalysisSetting e = elastic(0.3, flux, time), et = e;
        e.aspect = 1.25;
        et.aspect = 1 / 1.25;
        BOOST_TEST(limit(layout, e) == limit(transpose(layout), et),
                   boost::test_tools::tolerance(1e-4));  // the margin's tolerance, 1e-7
      }
    }
}

// RK2 with one particle off the centre on both axes and the paper's formulation: rho = 1
// along theta_x = 0 (the zero-speed mode sigma_xx of waves along y), and off that line rho - 1
// grows linearly with theta_x: a weak instability at every Courant number. An independent
// computation gives rho - 1 = 7.6e-7 at theta = (1e-3, pi / 2) and C = 0.4; the analysis finds
// it and puts C* near 0. Its cause is the volume term's inconsistency: with the consistent
// formulation (the default) the same particle is stable up to C = 0.999.
BOOST_AUTO_TEST_CASE(rk2_with_an_off_centre_particle_has_a_weak_long_wave_instability) {
  const CellLayout off = points({0.65, 0.4});
  const OneStepMap map = build_one_step_map(off, paper(elastic(0.3, dcu, rk2)));
  L2Criterion l2(map);
  BOOST_TEST(l2.spectral_radius(0.4, 1e-3, std::numbers::pi / 2) - 1 == 7.58e-7,
             boost::test_tools::tolerance(0.01));
  BOOST_TEST(l2.spectral_radius(0.4, 0.0, std::numbers::pi / 2) == 1.0,
             boost::test_tools::tolerance(1e-12));
  // The slope off the line, a = d rho / d theta_x at theta_x = 0+, grows like C^3, about
  // 0.016 C^3 per radian (one-sided second-order difference, as the criterion measures it).
  const auto slope = [&](double c) {
    const double d = 1e-3, y = std::numbers::pi / 2;
    const double f0 = l2.spectral_radius(c, 0, y) - 1, f1 = l2.spectral_radius(c, d, y) - 1,
                 f2 = l2.spectral_radius(c, 2 * d, y) - 1;
    return (4 * f1 - f2 - 3 * f0) / (2 * d);
  };
  BOOST_TEST(slope(0.1) / 1e-3 == 0.016, boost::test_tools::tolerance(0.1));
  BOOST_TEST(slope(0.2) / slope(0.1) == 8.0, boost::test_tools::tolerance(0.1));
  const CourantResult r = admissible_courant(off, paper(elastic(0.3, dcu, rk2)), Criterion::l2);
  BOOST_TEST(r.courant < 0.05);
  BOOST_TEST(std::abs(r.critical_theta_y) == std::numbers::pi / 2,
             boost::test_tools::tolerance(0.1));
  // Euler, and RK2 with the particle centred on one axis, have no such growth.
  BOOST_TEST(limit(off, paper(elastic(0.3, ctu, euler))) > 0.5);
  BOOST_TEST(limit(points({0.5, 0.3}), paper(elastic(0.3, dcu, rk2))) > 0.5);
  // The consistent formulation: no growth at C = 0.9, and the limit near 1.
  L2Criterion consistent(build_one_step_map(off, elastic(0.3, dcu, rk2)));
  BOOST_TEST(consistent.growth(0.9).value < 1e-13);
  BOOST_TEST(limit(off, elastic(0.3, dcu, rk2)) > 0.99);
}

// The 2D elastic system does not split into scalar waves: the monotone criterion is refused.
BOOST_AUTO_TEST_CASE(monotone_needs_scalar_waves) {
  BOOST_CHECK_THROW(
      admissible_courant(points({0.5, 0.5}), elastic(0.3, dcu, euler), Criterion::monotone),
      std::invalid_argument);
}

namespace {

// Growth per step of lib's 2D step on a periodic grid from random data, after `transient` steps.
template <class Physics>
double measured_growth(const CellLayout& layout, const AnalysisSetting& s, double courant,
                       int steps, int transient, int cells = 12) {
  PeriodicCells<Physics> grid(layout, cells, s);
  std::mt19937 rng(5);
  std::uniform_real_distribution<double> value(-1.0, 1.0);
  for (int p = 0; p < grid.num_particles(); ++p)
    for (int c = 0; c < Physics::n_comp; ++c) grid.state()(c, p) = value(rng);
  for (int k = 0; k < transient; ++k) grid.step(courant);
  const double start = grid.state().norm();
  for (int k = 0; k < steps; ++k) grid.step(courant);
  return std::pow(grid.state().norm() / start, 1.0 / steps);
}

// Largest spectral radius over the wavenumbers of a periodic grid of `cells` per axis.
double grid_radius(L2Criterion& l2, double courant, int cells) {
  double rho = 0;
  for (int i = 0; i < cells; ++i)
    for (int j = 0; j < cells; ++j)
      rho = std::max(rho, l2.spectral_radius(courant, 2 * std::numbers::pi * i / cells,
                                             2 * std::numbers::pi * j / cells));
  return rho;
}

}  // namespace

// Stepping the solver's operators: bounded for 1e4 steps at 0.99 C*, and above C* the solution
// grows at the rate of the grid's most unstable mode, as the analysis predicts (within 5%).
BOOST_AUTO_TEST_CASE(validation_by_stepping_the_solver) {
  struct Case {
    const char* name;
    CellLayout layout;
    AnalysisSetting setting;
  };
  const Case cases[] = {
      {"advection 1 centre dcu euler", points({0.5, 0.5}), advection(1, 1, dcu, euler)},
      {"advection 2 ctu euler", points({0.25, 0.5, 0.75, 0.5}), advection(1, 0.5, ctu, euler)},
      {"advection 4 regular dcu rk2", regular_layout(2, 2), advection(1, 1, dcu, rk2)},
      {"advection 3 random unequal ctu rk2", points({0.1, 0.3, 0.6, 0.9, 0.8, 0.45}, {1, 2, 0.5}),
       advection(0.7, 1, ctu, rk2)},
      {"elastic 1 centre dcu euler", points({0.5, 0.5}), elastic(0.3, dcu, euler)},
      {"elastic 1 off-axis ctu euler", points({0.3, 0.7}), elastic(0.3, ctu, euler)},
      {"elastic 2 dcu rk2", points({0.25, 0.5, 0.75, 0.5}), elastic(0.3, dcu, rk2)},
      {"elastic 4 regular ctu euler nu 0.45", regular_layout(2, 2), elastic(0.45, ctu, euler)},
  };
  const int cells = 12;
  for (const Case& c : cases) {
    BOOST_TEST_CONTEXT(c.name) {
      const bool adv = c.setting.model == Model::advection;
      const double cstar = limit(c.layout, c.setting);
      const auto growth = [&](double courant, int steps, int transient) {
        return adv ? measured_growth<Advection<2>>(c.layout, c.setting, courant, steps, transient,
                                                   cells)
                   : measured_growth<PlaneStrain>(c.layout, c.setting, courant, steps, transient,
                                                  cells);
      };
      BOOST_TEST(growth(0.99 * cstar, 10000, 0) <= 1.0 + 1e-9);
      // Above C*: the smallest C (step 0.01) where a mode of the grid grows by >= 2e-3 a step.
      L2Criterion l2(build_one_step_map(c.layout, c.setting));
      double courant = cstar, rho = 0;
      while (rho < 1.002 && courant < cstar + 1.0) rho = grid_radius(l2, courant += 0.01, cells);
      BOOST_TEST_REQUIRE(rho >= 1.002);
      const int steps = static_cast<int>(std::ceil(std::log(1e6) / std::log(rho)));
      const int transient = static_cast<int>(std::ceil(std::log(1e8) / std::log(rho)));
      const double measured = growth(courant, std::min(steps, 20000), std::min(transient, 20000));
      BOOST_TEST_MESSAGE(c.name << ": C* " << cstar << ", C " << courant << ", rho - 1 " << rho - 1
                                << ", measured - 1 " << measured - 1);
      BOOST_TEST(std::abs((measured - 1) - (rho - 1)) <= 0.05 * (rho - 1));
    }
  }
}

// A second route to C*: bisection on "rho <= 1 + 1e-10 at every point of a dense 97 x 192 grid
// of the half torus", written here without the search's margins, rays, slopes or refinement.
// The search must never be above it (a limit too high is a run that blows up) and within 1%
// below it (the dense grid cannot see what falls between its points, the search's refinement
// and long-wave margin can).
BOOST_AUTO_TEST_CASE(search_is_conservative_against_a_dense_scan) {
  struct Case {
    const char* name;
    CellLayout layout;
    AnalysisSetting setting;
    double lo, hi;
  };
  const Case cases[] = {
      {"advection 2 dcu euler", points({0.25, 0.5, 0.75, 0.5}), advection(1, 1, dcu, euler), 0.3,
       0.6},
      {"advection 2 ctu euler", points({0.25, 0.5, 0.75, 0.5}), advection(1, 1, ctu, euler), 0.4,
       0.8},
      {"advection 3 random dcu euler", points({0.1, 0.3, 0.6, 0.9, 0.8, 0.45}, {1, 2, 0.5}),
       advection(0.7, 1, dcu, euler), 0.1, 0.9},
      {"elastic 1 off-axis dcu euler", points({0.3, 0.7}), elastic(0.3, dcu, euler), 0.3, 0.9},
      // The refinement once spent itself on the neutral points of the axis lines and read 0.6030
      // here, above the dense scan's 0.6026.
      {"elastic 2 dcu euler", points({0.25, 0.5, 0.75, 0.5}), elastic(0.3, dcu, euler), 0.5, 0.7},
  };
  for (const Case& c : cases) {
    BOOST_TEST_CONTEXT(c.name) {
      L2Criterion l2(build_one_step_map(c.layout, c.setting));
      const auto fails = [&](double courant) {
        for (int i = 0; i <= 96; ++i)
          for (int j = 0; j < 192; ++j)
            if (l2.spectral_radius(courant, std::numbers::pi * i / 96,
                                   -std::numbers::pi + 2 * std::numbers::pi * (j + 1) / 192) >
                1 + 1e-10)
              return true;
        return false;
      };
      double lo = c.lo, hi = c.hi;
      BOOST_TEST_REQUIRE(!fails(lo));
      BOOST_TEST_REQUIRE(fails(hi));
      for (int k = 0; k < 30; ++k) {
        const double mid = 0.5 * (lo + hi);
        (fails(mid) ? hi : lo) = mid;
      }
      const double search = limit(c.layout, c.setting);
      BOOST_TEST_MESSAGE(c.name << ": dense scan " << lo << ", search " << search);
      BOOST_TEST(search <= lo * (1 + 1e-6));  // the margin's tolerance lets rho - 1 ~ 1e-7 pass
      BOOST_TEST(search >= 0.99 * lo);
    }
  }
}

// The consistent formulation's off-centre particle under RK2 loses stability to long waves in a
// cone 0.06 rad off an axis, about 0.01 rad wide at the onset: between the margin's rays (pi /
// 16 apart), and below the 2D scan's spacing. The search once read 0.998668 here, 2.5e-5 above
// the onset, where rho - 1 = 1.7e-7 per step at theta = (0.16, 0.01). A second route, written
// here: (rho - 1) / (2 - cos theta_x - cos theta_y) on circles of small radius, 4000 directions
// of the half plane each. At the search's C* it stays within the tolerance; 2e-5 above, it does
// not (the search is also tight).
BOOST_AUTO_TEST_CASE(long_waves_between_the_rays_bound_the_limit) {
  const CellLayout off = points({0.65, 0.4});
  const AnalysisSetting setting = elastic(0.3, dcu, rk2);
  L2Criterion l2(build_one_step_map(off, setting));
  const auto largest_margin = [&](double courant) {
    double largest = -1.0;
    for (const double r : {0.02, 0.05, 0.1, 0.2})
      for (int q = 0; q < 4000; ++q) {
        const double phi = std::numbers::pi * (q / 4000.0 - 0.5);
        const double tx = r * std::cos(phi), ty = r * std::sin(phi);
        const double s = 2 - std::cos(tx) - std::cos(ty);
        largest = std::max(largest, (l2.spectral_radius(courant, tx, ty) - 1) / s);
      }
    return largest;
  };
  const double search = limit(off, setting);
  BOOST_TEST_MESSAGE("search " << search << ": largest margin " << largest_margin(search));
  BOOST_TEST(largest_margin(search) <= kL2MarginTolerance2D);
  BOOST_TEST(largest_margin(search * (1 + 2e-5)) > kL2MarginTolerance2D);
}

// The torus is scanned by several threads but combined in a fixed order: the same C*, to the
// last bit, whatever the thread count.
BOOST_AUTO_TEST_CASE(thread_count_does_not_change_the_answer) {
  const CellLayout layout = points({0.3, 0.6, 0.8, 0.25}, {1.0, 2.0});
  for (FluxScheme flux : {dcu, ctu}) {
    const AnalysisSetting s = elastic(0.3, flux, rk2);
    omp_set_num_threads(1);
    const CourantResult one = admissible_courant(layout, s, Criterion::l2);
    omp_set_num_threads(2);
    const CourantResult two = admissible_courant(layout, s, Criterion::l2);
    BOOST_TEST(one.courant == two.courant);
    BOOST_TEST(one.failing_courant == two.failing_courant);
    BOOST_TEST(one.critical_theta == two.critical_theta);
    BOOST_TEST(one.critical_theta_y == two.critical_theta_y);
  }
}

// The 2D search scans C with a coarse margin and settles C* with a few probes and one full
// margin; the route it replaced evaluates the full margin at every scanned C (0.05 apart) and in
// every step of the refinement. Both must give the same C*: to 2e-5, as where C* is where a weak
// instability (a slope off a neutral line) crosses the margin's tolerance, the margin there stays
// within 1e-9 of the tolerance over 1e-5 in C and the two brackets may close at different points
// of that stretch (measured: 1.1e-5 for the unequal masses, 5e-6 off the centre; the others agree
// to the 7 digits given).
BOOST_AUTO_TEST_CASE(search_agrees_with_full_margins_at_every_scanned_courant) {
  struct Case {
    const char* name;
    CellLayout layout;
    AnalysisSetting setting;
    double tolerance = 2e-5;
  };
  const Case cases[] = {
      {"elastic 1 centred dcu euler", points({0.5, 0.5}), elastic(0.3, dcu, euler)},
      {"elastic 1 off-centre dcu rk2, paper's (weak long waves)", points({0.65, 0.4}),
       paper(elastic(0.3, dcu, rk2))},
      // C* is where a long-wave cone between the margin's rays crosses the tolerance
      // (long_waves_between_the_rays_bound_the_limit).
      {"elastic 1 off-centre dcu rk2", points({0.65, 0.4}), elastic(0.3, dcu, rk2)},
      {"elastic 1 off-axis ctu rk2", points({0.3, 0.7}), elastic(0.45, ctu, rk2)},
      {"elastic 2 unequal masses dcu euler", points({0.2, 0.3, 0.7, 0.6}, {1, 3}),
       elastic(0.3, dcu, euler)},
      {"elastic 4 regular dcu rk2", points({0.25, 0.25, 0.75, 0.25, 0.25, 0.75, 0.75, 0.75}),
       elastic(0.3, dcu, rk2)},
      {"advection 3 random ctu euler", points({0.1, 0.3, 0.6, 0.9, 0.8, 0.45}, {1, 2, 0.5}),
       advection(0.7, 1, ctu, euler)},
      {"advection 4 regular dcu rk2", points({0.25, 0.25, 0.75, 0.25, 0.25, 0.75, 0.75, 0.75}),
       advection(1, 1, dcu, rk2)},
  };
  for (const Case& c : cases) {
    BOOST_TEST_CONTEXT(c.name) {
      const OneStepMap map = build_one_step_map(c.layout, c.setting);
      SearchOptions options = default_search_options(Criterion::l2);
      options.margin_tolerance = kL2MarginTolerance2D;
      options.scan_step = kL2ScanStep2D;
      L2Criterion l2(map);
      const SearchResult full = search_admissible_courant(
          [&](double courant) {
            return l2.checked_margin(courant, options.margin_tolerance).value;
          },
          options, [&](double courant) { return l2.checked_margin(courant).value; });
      const CourantResult search = admissible_courant(map, Criterion::l2, options);
      BOOST_TEST_MESSAGE(c.name << ": full margins " << full.courant << " (" << full.evaluations
                                << " margins), search " << search.courant << " ("
                                << search.evaluations << ")");
      BOOST_TEST(search.courant == full.courant, boost::test_tools::tolerance(c.tolerance));
      BOOST_TEST(search.failing_courant > search.courant);
      BOOST_TEST(l2.checked_margin(search.courant).value <= options.margin_tolerance);
    }
  }
}

// Symmetries of the symbol are read off the one-step map (a signed permutation of the unknowns
// that maps every block B_d to B_{sigma d}), never assumed from the layout alone.
BOOST_AUTO_TEST_CASE(symmetries_of_the_symbol_are_found_not_assumed) {
  const CellLayout regular = points({0.25, 0.25, 0.75, 0.25, 0.25, 0.75, 0.75, 0.75});
  const CellLayout random = points({0.1, 0.2, 0.7, 0.3, 0.4, 0.8}, {1, 2, 1});
  AnalysisSetting stretched = elastic(0.3, dcu, rk2);
  stretched.aspect = 2.0;
  struct Case {
    const char* name;
    CellLayout layout;
    AnalysisSetting setting;
    bool mirror, swap;
  };
  const Case cases[] = {
      {"elastic regular", regular, elastic(0.3, dcu, rk2), true, true},
      {"elastic regular ctu", regular, elastic(0.3, ctu, euler), true, true},
      {"elastic regular, cells 2:1", regular, stretched, true, false},
      {"elastic on the mid-line y = 1/2", points({0.3, 0.5}), elastic(0.3, dcu, rk2), true, false},
      {"elastic on the diagonal", points({0.3, 0.3}), elastic(0.3, dcu, euler), false, true},
      {"elastic random", random, elastic(0.3, dcu, euler), false, false},
      {"advection a = b (waves go one way)", regular, advection(1, 1, dcu, euler), false, true},
      {"advection a != b", regular, advection(1, 0.5, dcu, euler), false, false},
  };
  std::mt19937 rng(7);
  std::uniform_real_distribution<double> angle(-std::numbers::pi, std::numbers::pi);
  for (const Case& c : cases) {
    BOOST_TEST_CONTEXT(c.name) {
      const OneStepMap map = build_one_step_map(c.layout, c.setting);
      L2Criterion l2(map);
      BOOST_TEST(l2.symmetries().at(0).mirror == c.mirror);
      BOOST_TEST(l2.symmetries().at(0).swap == c.swap);
      // What a symmetry claims holds at random wavenumbers; where none is found, the spectral
      // radius does differ somewhere.
      double mirror_gap = 0, swap_gap = 0;
      for (int k = 0; k < 20; ++k) {
        const double tx = angle(rng), ty = angle(rng), courant = 0.3;
        const double rho = l2.spectral_radius(courant, tx, ty);
        mirror_gap = std::max(mirror_gap, std::abs(l2.spectral_radius(courant, -tx, ty) - rho));
        swap_gap = std::max(swap_gap, std::abs(l2.spectral_radius(courant, ty, tx) - rho));
      }
      if (c.mirror) BOOST_TEST(mirror_gap < 1e-9);
      if (c.swap) BOOST_TEST(swap_gap < 1e-9);
      if (c.name == std::string("elastic random")) {
        BOOST_TEST(mirror_gap > 1e-6);
        BOOST_TEST(swap_gap > 1e-6);
      }
    }
  }
  // The sweeps over one class of symmetric points give the C* of the sweeps over all: moving one
  // particle by 1e-9 breaks the symmetries (and changes C* by far less than 1e-6).
  for (const TimeScheme time : {euler, rk2}) {
    CellLayout nudged = regular;
    nudged.positions[0] += 1e-9;
    const AnalysisSetting s = elastic(0.3, dcu, time);
    BOOST_TEST_REQUIRE(!L2Criterion(build_one_step_map(nudged, s)).symmetries().at(0).mirror);
    BOOST_TEST(limit(regular, s) == limit(nudged, s), boost::test_tools::tolerance(1e-6));
  }
}

// A cell's particles enter the one-step map only through its lumped masses, consistent mass and
// pseudo-stiffness (and RK2's near-empty test, on the lumped masses): sums of m_p times products
// of shape functions and their gradients, that is, for multilinear shapes, the layout's mass
// moments sum m x^a y^b with a, b <= 2. Two layouts with the same moments (different particle
// counts) must therefore have the same C*; one with other moments need not. 1D and 2D, Euler and
// RK2, DCU and CTU, both formulations.
BOOST_AUTO_TEST_CASE(layouts_with_equal_mass_moments_have_equal_limits) {
  // A symmetric three-point rule with the mean and second moment of two equal masses at x0, x1.
  struct Line {
    std::vector<double> x, m;
  };
  const auto matched = [](double x0, double x1, double spread) {
    const double mean = 0.5 * (x0 + x1), variance = 0.25 * (x1 - x0) * (x1 - x0);
    const double w = variance / (2 * spread * spread);
    return Line{{mean - spread, mean, mean + spread}, {w, 1 - 2 * w, w}};
  };
  const Line a = matched(0.25, 0.75, 0.4), b = matched(0.01, 0.51, 0.255);
  BOOST_TEST_REQUIRE(a.m[1] > 0.0);
  BOOST_TEST_REQUIRE(b.m[1] > 0.0);
  for (const TimeScheme time : {euler, rk2})
    for (const bool consistent : {true, false}) {
      const auto setting = [&](AnalysisSetting s) { return consistent ? s : paper(s); };
      BOOST_TEST_CONTEXT(to_string(time) << (consistent ? ", consistent" : ", paper")) {
        AnalysisSetting bar = setting(elastic(0.3, dcu, time));
        bar.dim = 1;
        const auto one = [&](std::vector<double> x, std::vector<double> m) {
          return limit({std::move(x), std::move(m), 1}, bar);
        };
        BOOST_TEST(one({0.25, 0.75}, {}) == one(a.x, a.m), boost::test_tools::tolerance(1e-6));
        BOOST_TEST(one({0.01, 0.51}, {}) == one(b.x, b.m), boost::test_tools::tolerance(1e-6));
        BOOST_TEST(std::abs(one({0.01, 0.51}, {}) - one({0.05, 0.55}, {})) > 1e-2);
      }
    }
  // 2D: 2 x 2 particles against the tensor product of the matched lines (3 x 3, unequal masses).
  const auto tensor = [](const Line& lx, const Line& ly) {
    std::vector<double> xy, m;
    for (std::size_t j = 0; j < ly.x.size(); ++j)
      for (std::size_t i = 0; i < lx.x.size(); ++i) {
        xy.insert(xy.end(), {lx.x[i], ly.x[j]});
        m.push_back(lx.m[i] * ly.m[j]);
      }
    return points(xy, m);
  };
  const Line square_x{{0.1, 0.6}, {0.5, 0.5}}, square_y{{0.05, 0.55}, {0.5, 0.5}};
  const CellLayout four = tensor(square_x, square_y);
  const CellLayout nine = tensor(matched(0.1, 0.6, 0.3), matched(0.05, 0.55, 0.28));
  for (const auto& [name, s] : {std::pair{"DCU Euler", elastic(0.3, dcu, euler)},
                                std::pair{"DCU RK2", elastic(0.3, dcu, rk2)},
                                std::pair{"CTU Euler", elastic(0.3, ctu, euler)}}) {
    BOOST_TEST_CONTEXT(name) {
      BOOST_TEST(limit(four, s) == limit(nine, s), boost::test_tools::tolerance(1e-6));
    }
  }
}

// A search at three significant digits whose first candidate, rounded down, fails below the last
// passing scan point (the solver's lattice corners search so): the scan steps back instead of
// asking for a refinement of an empty bracket, and the answer is the full search's, rounded down.
BOOST_AUTO_TEST_CASE(a_candidate_rounded_below_the_scan_point_steps_the_scan_back) {
  const OneStepMap map =
      build_one_step_map(points({0.0625, 0.4375, 0.625, 0.5}), elastic(0.3, dcu, euler));
  SearchOptions coarse = default_search_options(Criterion::l2);
  coarse.courant_tolerance = 1e-4;
  coarse.significant_digits = 3;
  const double full =
      admissible_courant(map, Criterion::l2, default_search_options(Criterion::l2)).courant;
  const double rounded = admissible_courant(map, Criterion::l2, coarse).courant;
  BOOST_TEST(rounded <= full);
  BOOST_TEST(rounded >= full - 1.5e-3);
}
