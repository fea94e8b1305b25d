// Automatic time step: dt from the stability analysis of the layouts the solver runs.
#define BOOST_TEST_MODULE time_step
#include <boost/test/unit_test.hpp>

#include "common/founding_paper.hpp"
#include "solver/scene_spectrum.hpp"
#include "solver/simulation.hpp"
#include "solver/time_step_control.hpp"

#include <nlohmann/json.hpp>
#include <stability/admissible_courant.hpp>

#include <cmath>
#include <omp.h>
#include <set>

using namespace dgmpm;
using nlohmann::json;

namespace {

using namespace dgmpm::test;

json steel() {
  return {{"steel", {{"young", E}, {"density", rho}}}};
}

json body(double lo, double hi, double v, json layout) {
  json b = {{"material", "steel"}, {"box", {{"min", {lo}}, {"max", {hi}}}}, {"velocity", {v}}};
  b.update(layout);
  return b;
}

// The founding paper's two-bar impact with moving particles, on a grid with room to move.
json moving_two_bar(json courant, const std::string& criterion = "") {
  json time = {{"end", 150 * dx / c}, {"integrator", "euler"}, {"courant", courant}};
  if (!criterion.empty()) time["criterion"] = criterion;
  return {
      {"dimension", 1},
      {"grid", {{"origin", {-0.4}}, {"cell_size", {dx}}, {"cells", {170}}}},
      {"materials", steel()},
      {"bodies",
       {body(0, 3, v0, {{"particles_per_cell", 1}}), body(3, 6, -v0, {{"particles_per_cell", 1}})}},
      {"time", time},
      {"particles_move", true}};
}

struct Extremes {
  double min_stress = 0, max_stress = 0, max_energy = 0, min_dt = 1e300;
  long steps = 0;
  bool failed = false;
};

// Steps to the end, recording the stress range and the largest energy after every step.
Extremes run_recording(BarSimulation& sim, double t_end) {
  Extremes r;
  r.max_energy = sim.energy();
  try {
    while (sim.time() < t_end * (1 - 1e-12)) {
      r.min_dt = std::min(r.min_dt, sim.stable_time_step());
      sim.step(std::min(sim.stable_time_step(), t_end - sim.time()));
      const auto s = sim.stress();
      r.min_stress = std::min(r.min_stress, s.minCoeff());
      r.max_stress = std::max(r.max_stress, s.maxCoeff());
      r.max_energy = std::max(r.max_energy, sim.energy());
      ++r.steps;
    }
  } catch (const std::runtime_error&) {
    r.failed = true;  // left the grid or overflowed: the instability ran away
  }
  return r;
}

}  // namespace

// Cells that come to hold two particles are unstable at C = 1 (admissible 0.686 for a regular
// pair): with the paper's formulation the run degrades badly; the consistent one (over-full
// cells then act as full cells of a denser material, slower) degrades less, but the energy still
// rises above its initial value (1.5%, and stresses reach -1.49 Z v0).
BOOST_AUTO_TEST_CASE(moving_two_bar_impact_degrades_at_courant_one) {
  const double t_end = 150 * dx / c, e0 = 0.5 * 6.0 * rho * v0 * v0;
  json doc = moving_two_bar(1.0);
  BarSimulation consistent(scene::parse_scene(doc));
  const Extremes r = run_recording(consistent, t_end);
  BOOST_TEST((r.failed || r.max_energy > 1.01 * e0));
  doc["formulation"] = "paper";
  BarSimulation paper(scene::parse_scene(doc));
  const Extremes p = run_recording(paper, t_end);
  BOOST_TEST((p.failed || p.max_energy > 1.5 * e0 || p.min_stress < -1.5 * Z * v0));
}

BOOST_AUTO_TEST_CASE(moving_two_bar_impact_with_auto_steps_stays_bounded) {
  const double t_end = 150 * dx / c, e0 = 0.5 * 6.0 * rho * v0 * v0;
  for (const char* criterion : {"l2", "monotone"}) {
    BOOST_TEST_CONTEXT(criterion) {
      BarSimulation sim(scene::parse_scene(moving_two_bar("auto", criterion)));
      const Extremes r = run_recording(sim, t_end);
      BOOST_TEST(!r.failed);
      // The Godunov fluxes dissipate; the admissible Courant numbers are found to 1e-9.
      BOOST_TEST(r.max_energy <= e0 * (1 + 1e-8));
      BOOST_TEST(sim.time_step_control()->layouts_analysed() > 1);
      BOOST_TEST(r.min_dt < 0.75 * dx / c);  // cells holding two particles limit dt
    }
  }
}

// "auto" with the monotone criterion should keep the stress inside the exact range [-Z v0, 0].
// With the paper's formulation it does so as long as no cell holds more than a full cell's
// mass; once the moving particles pile two into one cell, the operators no longer preserve
// constant states there (tests/lib_consistency.cpp) and new extrema appear whatever dt is.
// Asserted here: the range holds up to that step, the first value outside it appears next to the
// over-full cell, the run warns about that cell, and halving the safety factor does not remove
// the overshoot.
struct RangeHistory {
  long first_overfull = -1, first_outside = -1, steps = 0;
  int outside_cell = -1, nearest_overfull = -1;
  double min_stress = 0, max_stress = 0;
};

RangeHistory monotone_range_history(double safety) {
  json doc = moving_two_bar("auto", "monotone");
  doc["time"]["safety"] = safety;
  doc["formulation"] = "paper";
  BarSimulation sim(scene::parse_scene(doc));
  const auto& grid = sim.problem().grid;
  const auto& particles = sim.particles();
  const double t_end = 150 * dx / c, tol = 1e-9 * Z * v0;
  RangeHistory h;
  std::vector<double> fill(grid.num_cells());
  std::vector<int> cell(particles.size());
  Eigen::Matrix<double, 1, 1> xi;
  while (sim.time() < t_end * (1 - 1e-12)) {
    sim.step(std::min(sim.stable_time_step(), t_end - sim.time()));
    ++h.steps;
    std::fill(fill.begin(), fill.end(), 0.0);
    for (int p = 0; p < particles.size(); ++p) {
      cell[p] = grid.locate(particles.position.col(p), xi);
      fill[cell[p]] += particles.mass[p] / (rho * dx);
    }
    const auto s = sim.stress();
    h.min_stress = std::min(h.min_stress, s.minCoeff());
    h.max_stress = std::max(h.max_stress, s.maxCoeff());
    if (h.first_outside < 0)
      for (int p = 0; p < particles.size(); ++p)
        if (s[p] < -Z * v0 - tol || s[p] > tol) {
          h.first_outside = h.steps;
          h.outside_cell = cell[p];
          break;
        }
    if (h.first_overfull < 0)
      for (int k = 0; k < grid.num_cells(); ++k)
        if (fill[k] > 1 + 1e-6) {
          h.first_overfull = h.steps;
          h.nearest_overfull = k;
        }
  }
  BOOST_TEST_MESSAGE("safety " << safety << ": " << h.steps
                               << " steps, first over-full cell at step " << h.first_overfull
                               << ", first stress outside at step " << h.first_outside
                               << ", range [" << h.min_stress / (Z * v0) << ", "
                               << h.max_stress / (Z * v0) << "] Z v0");
  BOOST_TEST(sim.warnings().size() == 1u);
  if (!sim.warnings().empty())
    BOOST_TEST(sim.warnings()[0].find("step " + std::to_string(h.first_overfull) + ",") == 0u);
  return h;
}

BOOST_AUTO_TEST_CASE(monotone_auto_keeps_the_exact_range_until_a_cell_is_overfull) {
  const RangeHistory h = monotone_range_history(1.0);
  BOOST_TEST(h.first_overfull > 0);
  // Nothing outside [-Z v0, 0] while every cell is at most full (50 steps of impact).
  BOOST_TEST(h.first_outside > h.first_overfull);
  BOOST_TEST(std::abs(h.outside_cell - h.nearest_overfull) <= 1);
  BOOST_TEST(h.min_stress < -1.01 * Z * v0);  // and afterwards the overshoot is real

  // Half the step: more steps, the same overshoot; dt is not its cause.
  const RangeHistory half = monotone_range_history(0.5);
  BOOST_TEST(half.steps > 1.8 * h.steps);
  BOOST_TEST(half.first_outside > half.first_overfull);
  BOOST_TEST(half.min_stress < -1.01 * Z * v0);
  BOOST_TEST(half.max_stress > 0.01 * Z * v0);
}

// With the consistent formulation (the default) the over-full cells preserve constant states,
// and the monotone criterion does what it promises: no new extrema in the characteristic
// variables w = sigma -+ Z v
// (the decoupled system it analyses), whose range [-Z v0, Z v0] bounds the stress from below by
// -Z v0 at every step. The stress stays in the exact range [-Z v0, 0] until the release fronts,
// smeared over a few cells, meet at the contact just before the exact separation (t = 150 dx/c):
// w-monotonicity does not bound sigma = (w+ + w-) / 2 by 0 there, and a little tension appears.
BOOST_AUTO_TEST_CASE(the_consistent_formulation_makes_monotone_auto_keep_the_range) {
  json doc = moving_two_bar("auto", "monotone");
  BarSimulation sim(scene::parse_scene(doc));
  // tol: the cache's layout quantisation moves a particle by up to 2^-9 of its distance to a node,
  // so a step can land a hair above the real layout's limit (overshoots near 2e-9 Z v0 are seen).
  const double t_end = 150 * dx / c, tol = 1e-8 * Z * v0, e0 = sim.energy();
  double worst_w = 0, min_stress = 0, max_stress_before_140 = 0, max_stress = 0, max_energy = e0;
  long steps = 0;
  while (sim.time() < t_end * (1 - 1e-12)) {
    sim.step(std::min(sim.stable_time_step(), t_end - sim.time()));
    ++steps;
    const auto s = sim.stress();
    const auto v = sim.velocity();
    for (int p = 0; p < s.size(); ++p)
      worst_w = std::max({worst_w, std::abs(s[p] - Z * v[p]), std::abs(s[p] + Z * v[p])});
    min_stress = std::min(min_stress, s.minCoeff());
    max_stress = std::max(max_stress, s.maxCoeff());
    if (sim.time() <= 140 * dx / c) max_stress_before_140 = max_stress;
    max_energy = std::max(max_energy, sim.energy());
  }
  BOOST_TEST_MESSAGE("steps " << steps << ", max |w| / Z v0 - 1 " << worst_w / (Z * v0) - 1
                              << ", stress range [" << min_stress / (Z * v0) << ", "
                              << max_stress / (Z * v0) << "] Z v0");
  BOOST_TEST(worst_w <= Z * v0 + tol);
  BOOST_TEST(min_stress >= -Z * v0 - tol);
  BOOST_TEST(max_stress_before_140 <= tol);
  BOOST_TEST(max_stress <= 0.02 * Z * v0);
  BOOST_TEST(max_energy <= e0 * (1 + 1e-12));
  BOOST_TEST(sim.warnings().empty());  // no over-full warning: the consistent form has no cause
  // And the L2 criterion stays bounded with it.
  doc = moving_two_bar("auto", "l2");
  BarSimulation l2(scene::parse_scene(doc));
  const Extremes r = run_recording(l2, t_end);
  BOOST_TEST(!r.failed);
  BOOST_TEST(r.max_energy <= e0 * (1 + 1e-8));
}

BOOST_AUTO_TEST_CASE(mixed_layouts_take_the_two_particle_limit) {
  json doc = {
      {"dimension", 1},
      {"grid", {{"origin", {0.0}}, {"cell_size", {dx}}, {"cells", {100}}, {"periodic", true}}},
      {"materials", steel()},
      {"bodies",
       {body(0, 2, 1.0, {{"particles_per_cell", 2}}),
        body(2, 4, -1.0, {{"particles_per_cell", 1}})}},
      {"time", {{"end", 1000 * 0.686 * dx / c}, {"courant", "auto"}}}};
  BarSimulation sim(scene::parse_scene(doc));
  // Published: 2 regular particles per cell, Euler, L2: 0.686 +- 0.001.
  BOOST_TEST(std::abs(sim.stable_time_step() * c / dx - 0.686) <= 1e-3);
  BOOST_TEST(sim.time_step_control()->layouts_analysed() == 2);
  const double e0 = sim.energy();
  const Extremes r = run_recording(sim, doc["time"]["end"].get<double>());
  BOOST_TEST(!r.failed);
  BOOST_TEST(r.steps >= 999);
  BOOST_TEST(r.max_energy <= e0 * (1 + 1e-12));  // upwind fluxes dissipate, never create energy
}

BOOST_AUTO_TEST_CASE(bimaterial_dt_is_set_by_the_faster_material) {
  // The bars meet on a face; aluminium has the faster waves (c2 > c).
  BarSimulation sim(
      scene::parse_scene(bimaterial_bar(100, 10.0, {{"end", 1e-4}, {"courant", "auto"}})));
  BOOST_TEST(sim.stable_time_step() == dx / c2, boost::test_tools::tolerance(1e-9));
}

BOOST_AUTO_TEST_CASE(a_fixed_courant_above_the_admissible_one_warns_once) {
  json doc = {{"dimension", 1},
              {"grid", {{"origin", {0.0}}, {"cell_size", {dx}}, {"cells", {50}}}},
              {"materials", steel()},
              {"bodies", {body(0, 2, 1.0, {{"particles_per_cell", 2}})}},
              {"time", {{"end", 1e-5}, {"courant", 0.9}}}};
  BarSimulation sim(scene::parse_scene(doc));
  BOOST_TEST_REQUIRE(sim.warnings().size() == 1u);
  BOOST_TEST(sim.warnings()[0].find("0.686") != std::string::npos);
  BOOST_TEST(sim.stable_time_step() == 0.9 * dx / c, boost::test_tools::tolerance(1e-12));
  doc["time"]["courant"] = 0.5;
  BOOST_TEST(BarSimulation(scene::parse_scene(doc)).warnings().empty());
}

BOOST_AUTO_TEST_CASE(extreme_layouts_keep_dt_positive_and_the_run_finite) {
  const std::vector<std::pair<std::string, json>> layouts = {
      {"on a node", {{"positions_in_cell", {0.0, 0.5}}}},
      {"within 1e-9 of a node", {{"positions_in_cell", {1e-9, 0.5}}}},
      {"nearly coincident", {{"positions_in_cell", {0.5, 0.5 + 1e-9}}}},
      {"eight per cell", {{"particles_per_cell", 8}}}};
  for (const char* integrator : {"euler", "rk2"})
    for (const char* criterion : {"l2", "monotone"})
      for (const auto& [name, layout] : layouts) {
        BOOST_TEST_CONTEXT(name << ", " << integrator << ", " << criterion) {
          json doc = {{"dimension", 1},
                      {"grid", {{"origin", {0.0}}, {"cell_size", {dx}}, {"cells", {40}}}},
                      {"materials", steel()},
                      {"bodies", {body(0.4, 1.2, 10.0, layout)}},
                      {"time",
                       {{"end", 1.0},
                        {"integrator", integrator},
                        {"courant", "auto"},
                        {"criterion", criterion}}}};
          BarSimulation sim(scene::parse_scene(doc));
          const double dt = sim.stable_time_step();
          BOOST_TEST((std::isfinite(dt) && dt > 0));
          for (int k = 0; k < 200; ++k) sim.step(dt);  // throws on a non-finite state
          BOOST_TEST(sim.stress().allFinite());
          BOOST_TEST(sim.energy() <= 0.5 * rho * 0.8 * 100 * (1 + 1e-9));
        }
      }
}

BOOST_AUTO_TEST_CASE(a_cell_emptied_by_motion_keeps_dt_finite) {
  // Two bars flying apart: cells between them empty; particles cross nodes and share cells.
  json doc = {{"dimension", 1},
              {"grid", {{"origin", {0.0}}, {"cell_size", {dx}}, {"cells", {60}}}},
              {"materials", steel()},
              {"bodies",
               {body(0.8, 1.2, -200.0, {{"particles_per_cell", 1}}),
                body(1.2, 1.6, 200.0, {{"particles_per_cell", 1}})}},
              {"time", {{"end", 1.0}, {"courant", "auto"}}},
              {"particles_move", true}};
  BarSimulation sim(scene::parse_scene(doc));
  for (int k = 0; k < 400; ++k) {
    const double dt = sim.stable_time_step();
    BOOST_TEST_REQUIRE((std::isfinite(dt) && dt > 0));
    sim.step(dt);
  }
  BOOST_TEST(sim.stress().allFinite());
  BOOST_TEST(sim.velocity().allFinite());
}

// A bar whose ends fall mid-cell: its end cells are half full (4 of 8 particles, each of an eighth
// of a full cell's mass). The periodic analysis sees full cells; the small-cell rule scales their
// C* by the fill. Checked against the spectral radius of the whole scene's operator: safe, and
// more than half of it (0.43 against 0.80: the rule is what a lone particle of that fill needs to
// stay monotone, C <= f; these cells, consistent, act as full cells of a lighter material).
// 13 cells, the bar [0, 12 dx) shifted by half a cell, 8 particles per cell, RK2, "auto".
json bar_with_half_full_ends() {
  const int cells = 13;
  return {{"dimension", 1},
          {"grid", {{"origin", {-0.5 * dx}}, {"cell_size", {dx}}, {"cells", {cells}}}},
          {"materials", steel()},
          {"bodies", {body(0, (cells - 1) * dx, v0, {{"particles_per_cell", 8}})}},
          {"time", {{"end", 1.0}, {"integrator", "rk2"}, {"courant", "auto"}}}};
}

BOOST_AUTO_TEST_CASE(half_full_end_cells_take_the_small_cell_rule) {
  const json doc = bar_with_half_full_ends();
  BarSimulation sim(scene::parse_scene(doc));
  const double used = sim.stable_time_step() * c / dx;
  const double full_layout =
      stability::admissible_courant({{0.0625, 0.1875, 0.3125, 0.4375}, {}},
                                    stability::TimeScheme::rk2, stability::Criterion::l2)
          .courant;
  json fixed = doc;
  fixed["time"]["courant"] = 0.5;
  const double scene_limit = analyse_scene_spectrum(scene::parse_scene(fixed)).courant;
  BOOST_TEST_MESSAGE("used " << used << " layout " << full_layout << " scene " << scene_limit);
  BOOST_TEST(used == 0.5 * full_layout, boost::test_tools::tolerance(1e-12));
  BOOST_TEST(full_layout > scene_limit);  // the periodic model alone would be unstable here
  BOOST_TEST(used <= scene_limit);
  BOOST_TEST(used >= 0.5 * scene_limit);
  // Stable: the energy never grows (the consistent formulation keeps the bar rigid: below).
  // With the paper's form a part-full cell breaks consistency (tests/lib_consistency.cpp), its
  // ends radiate stress waves and the energy settles near 3.3 e0.
  const double e0 = sim.energy(), dt = sim.stable_time_step();
  const Extremes first = run_recording(sim, 500 * dt);
  const double e500 = sim.energy();
  const Extremes later = run_recording(sim, 2000 * dt);
  BOOST_TEST_MESSAGE("energy / e0: max " << std::max(first.max_energy, later.max_energy) / e0
                                         << ", at 500 steps " << e500 / e0 << ", at 2000 "
                                         << sim.energy() / e0);
  BOOST_TEST((!first.failed && !later.failed));
  BOOST_TEST(sim.energy() <= e500 * (1 + 1e-10));  // settled, to round-off
  // Without the rule (the full layout's C*, above the scene limit found above) it blows up.
  json without = doc;
  without["time"]["courant"] = full_layout;
  BarSimulation unstable(scene::parse_scene(without));
  const Extremes u = run_recording(unstable, 2000 * full_layout * dx / c);
  BOOST_TEST((u.failed || u.max_energy > 1e6 * e0));
}

// With the consistent formulation the half-full end cells preserve the rigid translation: no
// stress appears, the energy stays put.
BOOST_AUTO_TEST_CASE(the_consistent_formulation_keeps_a_bar_with_half_full_ends_rigid) {
  json doc = bar_with_half_full_ends();
  BarSimulation sim(scene::parse_scene(doc));
  const double e0 = sim.energy();
  const Extremes r = run_recording(sim, 2000 * sim.stable_time_step());
  BOOST_TEST(!r.failed);
  BOOST_TEST(r.steps == 2000);
  BOOST_TEST(std::max(-r.min_stress, r.max_stress) <= 1e-9 * Z * v0);
  BOOST_TEST(r.max_energy <= e0 * (1 + 1e-12));
  BOOST_TEST((sim.velocity().array() - v0).abs().maxCoeff() <= 1e-9 * v0);
}

// The whole-scene analysis steps through the scene's own stepper, formulation included: the
// consistent form changes the half-full end cells' volume term, and the scene's limit moves with
// it (0.4565 with the paper's form, 0.64 with the consistent one).
BOOST_AUTO_TEST_CASE(scene_spectrum_honours_the_formulation) {
  json doc = bar_with_half_full_ends();
  doc["time"]["courant"] = 0.5;
  const double consistent = analyse_scene_spectrum(scene::parse_scene(doc)).courant;
  doc["formulation"] = "paper";
  const double paper = analyse_scene_spectrum(scene::parse_scene(doc)).courant;
  BOOST_TEST_MESSAGE("scene limit with the paper's form " << paper << ", consistent "
                                                          << consistent);
  BOOST_TEST(consistent > paper + 0.1);
}

// time.check_scene_every: the whole scene's frozen operator checked at the chosen step. A bar
// whose part-full end cell holds one particle 0.01 of a cell from a node, under the paper's
// formulation with RK2: its layouts admit C = 0.5 (L2), the scene's operator about 0.02
// (`courant --scene`). Without the guard the run blows up; with it the step is halved until the
// scene's spectral radius is at most 1, and the run stays bounded. (Not below its initial energy:
// the paper's operator there is far from normal, and a spectral radius of 1 allows the transient
// rise of 31% seen here; the consistent formulation, the default, has neither the instability nor
// the rise: tests/energy_bound_scenes.py.)
BOOST_AUTO_TEST_CASE(the_scene_guard_halves_the_step_where_the_layouts_miss_the_scene) {
  const auto scene_doc = [](json time, bool move) {
    return json{{"dimension", 1},
                {"grid", {{"origin", {0.0}}, {"cell_size", {dx}}, {"cells", {14}}}},
                {"materials", steel()},
                {"bodies", {body(0.0, 10.015 * dx, 10.0, {{"positions_in_cell", {0.01, 0.51}}})}},
                {"time", time},
                {"formulation", "paper"},
                {"particles_move", move}};
  };
  const double t_end = 1500 * 0.015 * dx / c;
  json time = {{"end", t_end}, {"integrator", "rk2"}, {"courant", "auto"}, {"criterion", "l2"}};
  BarSimulation unguarded(scene::parse_scene(scene_doc(time, false)));
  const double e0 = unguarded.energy();
  BOOST_TEST(unguarded.stable_time_step() * c / dx == 0.5, boost::test_tools::tolerance(1e-6));
  const Extremes blown = run_recording(unguarded, t_end);
  BOOST_TEST((blown.failed || blown.max_energy > 10 * e0));

  time["check_scene_every"] = 1;
  BarSimulation guarded(scene::parse_scene(scene_doc(time, false)));
  const double courant = guarded.stable_time_step() * c / dx;
  // The scene's own limit, from courant --scene's search, bounds the guarded step.
  json fixed = scene_doc({{"end", t_end}, {"integrator", "rk2"}, {"courant", 0.5}}, false);
  const double limit = analyse_scene_spectrum(scene::parse_scene(fixed)).courant;
  BOOST_TEST_MESSAGE("guarded C " << courant << ", scene limit " << limit);
  BOOST_TEST(courant <= limit);
  BOOST_TEST(courant >= 0.5 * limit);  // halved no further than needed
  BOOST_TEST_REQUIRE(guarded.warnings().size() >= 1u);
  BOOST_TEST(guarded.warnings().back().find("the whole scene's operator has spectral radius") !=
             std::string::npos);
  const Extremes r = run_recording(guarded, t_end);
  BOOST_TEST(!r.failed);
  BOOST_TEST(r.max_energy <= 1.5 * e0);

  // Moving particles: checked every 10 steps, the factor kept in between.
  time["check_scene_every"] = 10;
  BarSimulation moving(scene::parse_scene(scene_doc(time, true)));
  const Extremes m = run_recording(moving, t_end);
  BOOST_TEST(!m.failed);
  BOOST_TEST(m.max_energy <= 1.6 * e0);
  BOOST_TEST(m.min_dt * c / dx <= limit);
}

// Moving cells of two to four particles, of equal masses and (where a soft and a stiff body share
// a cell) unequal ones, take their C* from the cache of lattice boxes on the threads: choosing
// the step again on the same particles sends no cell to the serial path and gives the step the
// serial path computed; one and two threads choose the same step.
BOOST_AUTO_TEST_CASE(moving_layouts_of_a_few_particles_are_looked_up_on_threads) {
  json materials = steel();
  materials["soft"] = {{"young", E / 4}, {"density", rho / 2}};
  json soft = body(1.0, 2.05, 2 * v0, {{"particles_per_cell", 3}});
  soft["material"] = "soft";
  const json doc = {{"dimension", 1},
                    {"grid", {{"origin", {-0.5}}, {"cell_size", {0.1}}, {"cells", {40}}}},
                    {"materials", materials},
                    {"bodies",
                     {body(0.0, 1.0, v0, {{"particles_per_cell", 2}}), soft,
                      body(2.05, 3.0, -v0, {{"particles_per_cell", 4}})}},
                    {"time", {{"end", 1e-3}, {"courant", "auto"}, {"criterion", "l2"}}},
                    {"particles_move", true}};
  const scene::Scene scene = scene::parse_scene(doc);
  BarProblem problem = make_bar_problem(scene);
  Discretisation<ElasticBar> disc;
  disc.set_formulation(scene.formulation);
  disc.build(problem.grid, problem.particles, problem.materials);
  std::set<int> counts;
  bool unequal = false;
  for (int c = 0; c < disc.num_cells(); ++c) {
    if (!disc.occupied(c)) continue;
    counts.insert(disc.cell_end(c) - disc.cell_begin(c));
    for (int e = disc.cell_begin(c); e < disc.cell_end(c); ++e)
      unequal = unequal || problem.particles.mass[disc.entry_particle(e)] !=
                               problem.particles.mass[disc.entry_particle(disc.cell_begin(c))];
  }
  BOOST_TEST((counts.count(2) && counts.count(3) && counts.count(4)));
  BOOST_TEST(unequal);
  const int threads = omp_get_max_threads();
  const auto choose = [&](int team) {
    omp_set_num_threads(team);
    TimeStepControl<ElasticBar> control(scene, problem.max_wave_speed());
    const double first =
        control.time_step(problem.grid, disc, problem.particles, problem.materials);
    BOOST_TEST(control.serial_cells() > 0);  // the boxes bounded, on the serial path
    const double again =
        control.time_step(problem.grid, disc, problem.particles, problem.materials);
    BOOST_TEST(control.serial_cells() == 0);
    BOOST_TEST(again == first);
    return first;
  };
  const double one = choose(1), two = choose(2);
  omp_set_num_threads(threads);
  BOOST_TEST(std::isfinite(one));
  BOOST_TEST(one > 0);
  BOOST_TEST(two == one);
}
