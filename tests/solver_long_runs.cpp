// "auto" never steps above the limit: where the admissible Courant number is exactly 1 (one
// particle per cell, Euler; two per cell, RK2; 2D DCU RK2 with one centred particle), millions of
// steps at "auto" keep the energy at its initial value to round-off. (A step 1e-9 above the limit
// made it grow by 0.2% over 5e6 steps; round-off alone stays below 1e-9.)
#define BOOST_TEST_MODULE solver_long_runs
#include <boost/test/unit_test.hpp>

#include "solver/scene.hpp"
#include "solver/simulation.hpp"

#include <nlohmann/json.hpp>

#include <algorithm>
#include <string>

using namespace dgmpm;
using nlohmann::json;

namespace {

// A periodic grid filled by two bodies moving apart: waves cross the grid for ever, and the
// energy can only stay or decay.
json periodic_scene(int dim, const std::string& integrator, int particles_per_cell, int cells) {
  json ppc = dim == 1 ? json{particles_per_cell} : json{particles_per_cell, 1};
  const double length = cells * 0.1;
  const auto box = [&](double lo, double hi) {
    return dim == 1 ? json{{"min", {lo}}, {"max", {hi}}}
                    : json{{"min", {lo, 0.0}}, {"max", {hi, 0.4}}};
  };
  const auto velocity = [&](double v) { return dim == 1 ? json{v} : json{v, 0.3 * v}; };
  json grid = {{"origin", dim == 1 ? json{0.0} : json{0.0, 0.0}},
               {"cell_size", dim == 1 ? json{0.1} : json{0.1, 0.1}},
               {"cells", dim == 1 ? json{cells} : json{cells, 4}},
               {"periodic", true}};
  json doc = {{"dimension", dim},
              {"grid", grid},
              {"materials", {{"steel", {{"young", 2e11}, {"poisson", 0.3}, {"density", 7800}}}}},
              {"bodies",
               {{{"material", "steel"},
                 {"box", box(0, 0.5 * length)},
                 {"velocity", velocity(1.0)},
                 {"particles_per_cell", ppc}},
                {{"material", "steel"},
                 {"box", box(0.5 * length, length)},
                 {"velocity", velocity(-1.0)},
                 {"particles_per_cell", ppc}}}},
              {"time", {{"end", 1.0}, {"integrator", integrator}, {"courant", "auto"}}}};
  return doc;
}

// Largest relative energy excess over the initial value during `steps` steps at "auto".
double worst_excess(const json& doc, long steps, double expected_courant, double h, double c) {
  const scene::Scene s = scene::parse_scene(doc);
  return with_physics(s, [&](auto physics) {
    Simulation<typename decltype(physics)::type> sim(s);
    BOOST_TEST(sim.stable_time_step() * c / h == expected_courant,
               boost::test_tools::tolerance(1e-14));
    const double e0 = sim.energy();
    double worst = 0;
    for (long k = 1; k <= steps; ++k) {
      sim.step(sim.stable_time_step());
      if (k % 4096 == 0) worst = std::max(worst, sim.energy() / e0 - 1);
    }
    return std::max(worst, sim.energy() / e0 - 1);
  });
}

}  // namespace

BOOST_AUTO_TEST_CASE(one_dimension_five_million_steps) {
  const double c = std::sqrt(2e11 / 7800);
  for (const auto& [integrator, ppc] : {std::pair{"euler", 1}, std::pair{"rk2", 2}}) {
    BOOST_TEST_CONTEXT(integrator << ", " << ppc << " per cell") {
      const double excess =
          worst_excess(periodic_scene(1, integrator, ppc, 8), 5'000'000, 1.0, 0.1, c);
      BOOST_TEST_MESSAGE(integrator << ": worst energy excess " << excess);
      BOOST_TEST(excess <= 1e-9);  // round-off: 4e-11 (Euler), 2e-10 (RK2) over 5e6 steps
    }
  }
}

BOOST_AUTO_TEST_CASE(two_dimensions_a_million_steps) {
  const double nu = 0.3, cp = std::sqrt(2e11 * (1 - nu) / ((1 + nu) * (1 - 2 * nu) * 7800));
  json doc = periodic_scene(2, "rk2", 1, 4);
  doc["flux"] = "dcu";
  const double excess = worst_excess(doc, 1'000'000, 1.0, 0.1, cp);
  BOOST_TEST_MESSAGE("2D DCU RK2: worst energy excess " << excess);
  BOOST_TEST(excess <= 1e-9);
}
