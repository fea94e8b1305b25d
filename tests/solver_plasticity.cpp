// Solids that yield, through the solver: the shipped plastic bar impact against the exact plateau
// of its elastic-plastic wave pair (DGMPM Euler and RK2, fixed and moving particles, and the MPM
// baseline's three variants), the energy balance at every step, a stiff Perzyna relaxation at
// the elastic time step, elastic and plastic materials side by side, and the scene's errors.
#define BOOST_TEST_MODULE solver_plasticity
#include <boost/test/unit_test.hpp>

#include "solver/problem.hpp"
#include "solver/scene.hpp"
#include "solver/simulation.hpp"

#include <nlohmann/json.hpp>

#include <cmath>
#include <fstream>
#include <string>

using namespace dgmpm;
using nlohmann::json;

namespace {

constexpr double E = 2e11, rho = 7800, sigma_y = 4e8, c_kin = 15e9, v0 = 30.55;

json shipped() {
  std::ifstream in(std::string(DGMPM_TEST_SOURCE_DIR) + "/scenes/bar_plastic_impact.json");
  return json::parse(in);
}

// The exact plateau between the plastic fronts (uniaxial stress, linear kinematic hardening).
double plateau() {
  const double c = std::sqrt(E / rho), et = E * c_kin / (E + c_kin), cp = std::sqrt(et / rho);
  return sigma_y * (1 - cp / c) + rho * cp * v0;
}
double plastic_speed() {
  return std::sqrt(E * c_kin / (E + c_kin) / rho);
}

struct Result {
  double mean_stress = 0, mean_plastic_strain = 0;  // over the plateau's particles
  long steps = 0;
  bool balanced = true;  // total energy <= initial at every step
  double dissipated = 0, stored = 0;
};

// Steps the scene to its end, checking the energy at every step, and averages over the particles
// well inside the plastic fronts (the first-order fronts spread over about 0.3 m by then).
Result run(const json& doc) {
  Simulation<ElastoPlasticBar> sim(scene::parse_scene(doc));
  const double e0 = sim.energy(), t_end = doc["time"]["end"].get<double>();
  Result r;
  while (sim.time() < t_end) {
    sim.advance_to(std::min(t_end, sim.time() + sim.stable_time_step()));
    r.balanced = r.balanced && sim.energy() <= e0 * (1 + 1e-12);
  }
  r.steps = sim.steps();
  const auto& p = sim.particles();
  int count = 0;
  for (int i = 0; i < p.size(); ++i) {
    if (std::abs(p.position(0, i) - 3.0) > 0.3 * plastic_speed() * sim.time()) continue;
    r.mean_stress += -p.state(0, i) * rho;
    r.mean_plastic_strain += -p.internal(ElastoPlasticBar::plastic_strain, i);
    ++count;
  }
  BOOST_TEST_REQUIRE(count > 5);
  r.mean_stress /= count;
  r.mean_plastic_strain /= count;
  r.dissipated = sim.energy_parts().dissipated;
  r.stored = sim.energy_parts().stored;
  return r;
}

}  // namespace

BOOST_AUTO_TEST_CASE(the_shipped_impact_reaches_the_exact_plateau_by_every_route) {
  const double exact = plateau();
  for (const std::string method : {"dgmpm", "mpm-usl", "mpm-usf", "mpm-musl"})
    for (const std::string integrator : {"euler", "rk2"})
      for (const bool move : {false, true}) {
        if (method != "dgmpm" && (integrator == "rk2" || move)) continue;
        json doc = shipped();
        doc["method"] = method;
        doc["time"]["integrator"] = integrator;
        doc["particles_move"] = move;
        if (method != "dgmpm") doc["time"]["courant"] = 0.5;
        BOOST_TEST_CONTEXT(method << ", " << integrator << (move ? ", moving" : ", fixed")) {
          const Result r = run(doc);
          if (method == "dgmpm") BOOST_TEST(r.balanced);  // MPM makes no such promise
          BOOST_TEST(r.dissipated > 0);
          BOOST_TEST(r.stored > 0);
          // DGMPM's plateau: at Courant 1 (auto, one centred particle per cell) an odd-even
          // ripple of 0.2-0.4% that the scheme does not damp rides on it; MPM's oscillates more.
          // USF and MUSL pile up 9% too much plastic strain near the impact plane.
          const bool dg = method == "dgmpm";
          BOOST_TEST(r.mean_stress == exact, boost::test_tools::tolerance(dg ? 2e-3 : 2e-2));
          BOOST_TEST(r.mean_plastic_strain == (exact - sigma_y) / c_kin,
                     boost::test_tools::tolerance(dg ? 1e-2 : 0.15));
        }
      }
}

// tau = 1e-12 s, a million times below the time step: the run takes the elastic steps, stays
// bounded and lands on the rate-independent plateau (its distance, like tau^(1/n), is 2e-3 here).
BOOST_AUTO_TEST_CASE(a_stiff_relaxation_runs_at_the_elastic_time_step) {
  const Result plastic = run(shipped());
  json doc = shipped();
  auto& steel = doc["materials"]["steel"];
  steel["model"] = "elasto_viscoplastic";
  steel["relaxation_time"] = 1e-12;
  steel["rate_exponent"] = 4.37;
  const Result viscous = run(doc);
  BOOST_TEST(viscous.steps == plastic.steps);
  BOOST_TEST(viscous.balanced);
  BOOST_TEST(viscous.mean_stress > plastic.mean_stress);  // the overstress keeps it above
  BOOST_TEST(viscous.mean_stress == plastic.mean_stress, boost::test_tools::tolerance(1e-2));
  // A slow relaxation (tau = 1e6 s, dp / dt = (f / sigma_y)^n / tau about 2e-5 / s): hardly any
  // plastic flow, the elastic impact's stress rho c v0.
  steel["relaxation_time"] = 1e6;
  const Result slow = run(doc);
  BOOST_TEST(slow.mean_plastic_strain < 1e-8);
  BOOST_TEST(slow.mean_stress == rho * std::sqrt(E / rho) * v0, boost::test_tools::tolerance(1e-3));
}

BOOST_AUTO_TEST_CASE(elastic_and_plastic_materials_share_a_scene) {
  json doc = shipped();
  doc["materials"]["rubber"] = {{"model", "linear_elastic"}, {"young", 2e11}, {"density", 7800}};
  doc["bodies"][1]["material"] = "rubber";  // the right half never yields
  const scene::Scene scene = scene::parse_scene(doc);
  bool plastic_physics = false;
  with_physics(scene, [&](auto physics) {
    plastic_physics = std::is_same_v<typename decltype(physics)::type, ElastoPlasticBar>;
  });
  BOOST_TEST(plastic_physics);
  Simulation<ElastoPlasticBar> sim(scene);
  const double e0 = sim.energy();
  sim.advance_to(4e-4);
  BOOST_TEST(sim.energy() <= e0);
  const auto& p = sim.particles();
  double left = 0, right = 0;
  for (int i = 0; i < p.size(); ++i)
    (p.position(0, i) < 3.0 ? left : right) += std::abs(p.internal(0, i));
  BOOST_TEST(left > 0);
  BOOST_TEST(right == 0.0);
}

BOOST_AUTO_TEST_CASE(plastic_materials_are_checked_with_their_keys) {
  const auto message = [](const json& doc) {
    try {
      scene::parse_scene(doc, "s.json");
    } catch (const scene::SceneError& e) {
      return std::string(e.what());
    }
    return std::string("accepted");
  };
  const auto with = [](const std::string& key, const json& value) {
    json doc = shipped();
    if (value.is_null())
      doc["materials"]["steel"].erase(key);
    else
      doc["materials"]["steel"][key] = value;
    return doc;
  };
  const auto contains = [](const std::string& text, const std::string& part) {
    return text.find(part) != std::string::npos;
  };
  std::string m = message(with("yield_stress", nullptr));
  BOOST_TEST(contains(m, "materials.steel.yield_stress: missing required key"), m);
  m = message(with("yield_stress", -1.0));
  BOOST_TEST(contains(m, "materials.steel.yield_stress: value -1"), m);
  m = message(with("kinematic_hardening", -5.0));
  BOOST_TEST(contains(m, "allowed: a number >= 0 (Pa)"), m);
  m = message(with("relaxation_time", 1e-6));  // not an elastoplastic key
  BOOST_TEST(contains(m, "materials.steel.relaxation_time: unknown key"), m);
  json viscous = with("model", "elasto_viscoplastic");
  m = message(viscous);
  BOOST_TEST(contains(m, "materials.steel.relaxation_time: missing required key"), m);
  viscous["materials"]["steel"]["relaxation_time"] = 1e-6;
  viscous["materials"]["steel"]["rate_exponent"] = 0.5;
  m = message(viscous);
  BOOST_TEST(contains(m, "materials.steel.rate_exponent: value 0.5 is not allowed"), m);
  json plate = {{"dimension", 2},
                {"grid", {{"origin", {0, 0}}, {"cell_size", {1, 1}}, {"cells", {2, 2}}}},
                {"materials", shipped()["materials"]},
                {"bodies",
                 {{{"material", "steel"},
                   {"box", {{"min", {0, 0}}, {"max", {2, 2}}}},
                   {"particles_per_cell", {1, 1}}}}},
                {"time", {{"end", 1e-4}}}};
  plate["materials"]["steel"]["poisson"] = 0.3;
  m = message(plate);
  BOOST_TEST(contains(m, "materials.steel.model: value \"elastoplastic\" is not available in 2D"),
             m);
  json exact = shipped();
  exact["exact"] = "bar";
  BOOST_CHECK_THROW(make_simulation(scene::parse_scene(exact)), scene::SceneError);
}
