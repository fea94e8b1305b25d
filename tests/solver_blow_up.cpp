// A run that blows up fails: energy above time.blow_up_factor times (initial energy + work of
// the loads) stops it with the step, time, particle and cell; stable runs, loaded or not, DGMPM
// or MPM, never trip it; the check can be raised or turned off in the scene.
#define BOOST_TEST_MODULE solver_blow_up
#include <boost/test/unit_test.hpp>

#include "solver/scene.hpp"
#include "solver/simulation.hpp"

#include <nlohmann/json.hpp>

#include <cctype>
#include <filesystem>
#include <fstream>
#include <string>

using namespace dgmpm;
using nlohmann::json;

namespace {

json two_bar(const std::string& method, double courant) {
  const auto bar = [](double lo, double hi, double v) {
    return json{{"material", "steel"},
                {"box", {{"min", {lo}}, {"max", {hi}}}},
                {"velocity", {v}},
                {"particles_per_cell", 1}};
  };
  return {{"dimension", 1},
          {"method", method},
          {"grid", {{"origin", {0.0}}, {"cell_size", {0.04}}, {"cells", {150}}}},
          {"materials", {{"steel", {{"young", 2e11}, {"density", 7800}}}}},
          {"bodies", {bar(0, 3, 1), bar(3, 6, -1)}},
          {"time", {{"end", 4e-3}, {"integrator", "euler"}, {"courant", courant}}}};
}

std::string failure(const json& doc) {
  try {
    BarSimulation(scene::parse_scene(doc)).run({});
  } catch (const std::runtime_error& e) {
    return e.what();
  }
  return "";
}

// The step a failure message starts with ("step N, t = ..."), -1 if none.
long step_of(const std::string& what) {
  if (what.rfind("step ", 0) != 0) return -1;
  return std::stol(what.substr(5));
}

}  // namespace

// DGMPM above its limit and MPM USL at Courant 1 (growth |1 - 4 C^2| = 3 per step) stop within
// the first checks, naming where; the message carries step, time, particle, cell and the factor.
BOOST_AUTO_TEST_CASE(unbounded_growth_stops_the_run) {
  for (const auto& [method, courant] :
       {std::pair{"dgmpm", 1.5}, std::pair{"mpm-usl", 1.0}, std::pair{"dgmpm", 1.01}}) {
    BOOST_TEST_CONTEXT(method << " at " << courant) {
      const std::string what = failure(two_bar(method, courant));
      BOOST_TEST_MESSAGE(what);
      BOOST_TEST(what.find("the run is unstable") != std::string::npos);
      BOOST_TEST_REQUIRE(step_of(what) >= 16);
      const auto particle = what.find("; largest on particle ");
      BOOST_TEST_REQUIRE(particle != std::string::npos);
      const auto x = what.find(" (x = ", particle), cell = what.find(", cell ", particle);
      BOOST_TEST((x != std::string::npos && cell != std::string::npos && cell > x));
      BOOST_TEST(std::isdigit(static_cast<unsigned char>(what[cell + 7])));
      BOOST_TEST(what.find("time.blow_up_factor 10") != std::string::npos);
    }
  }
}

// Raising the factor lets the growth go further; turning the check off runs to the end, where
// the energy is far above the bound (the unstable case run on purpose).
BOOST_AUTO_TEST_CASE(the_check_can_be_raised_or_turned_off) {
  json doc = two_bar("dgmpm", 1.5);
  const long at_10 = step_of(failure(doc));
  doc["time"]["blow_up_factor"] = 1e100;
  const long at_1e100 = step_of(failure(doc));
  BOOST_TEST(at_10 > 0);
  BOOST_TEST(at_1e100 > at_10 + 100);
  doc["time"].erase("blow_up_factor");
  doc["time"]["blow_up_check"] = false;
  doc["time"]["end"] = 2e-4;  // before the overflow
  BarSimulation sim(scene::parse_scene(doc));
  const double e0 = sim.energy();
  const RunSummary s = sim.run({});
  BOOST_TEST(s.energy_final > 1e6 * e0);
}

// Stable runs never trip it: the shipped scenes (DGMPM and MPM, with and without loads, 1D and
// 2D) and the plate under MPM USF, whose load work is the reference.
BOOST_AUTO_TEST_CASE(stable_runs_pass) {
  const auto dir = std::filesystem::path(DGMPM_TEST_SOURCE_DIR) / "scenes";
  int runs = 0;
  for (const auto& entry : std::filesystem::directory_iterator(dir)) {
    if (entry.path().extension() != ".json") continue;
    for (const char* method : {"dgmpm", "mpm-usf"}) {
      BOOST_TEST_CONTEXT(entry.path().filename() << " " << method) {
        scene::Scene s = scene::load_scene(entry.path().string());
        if (std::string(method) != "dgmpm") {
          if (s.method != scene::Method::dgmpm) continue;
          json doc = json::parse(std::ifstream(entry.path()));
          doc["method"] = method;
          doc["time"]["courant"] = 0.5;
          doc.erase("flux");
          doc.erase("formulation");
          doc.erase("exact");
          doc.erase("plane_wave");
          doc.erase("particles_move");
          if (doc["time"].contains("criterion")) doc["time"].erase("criterion");
          if (doc["time"].contains("safety")) doc["time"].erase("safety");
          try {
            s = scene::parse_scene(doc);
          } catch (const scene::SceneError&) {
            continue;  // a DGMPM-only feature
          }
        }
        s.output = {};
        BOOST_CHECK_NO_THROW(with_physics(
            s, [&](auto physics) { Simulation<typename decltype(physics)::type>(s).run({}); }));
        ++runs;
      }
    }
  }
  BOOST_TEST(runs >= 12);
}

BOOST_AUTO_TEST_CASE(bad_settings_are_refused) {
  for (const json& bad :
       {json{{"blow_up_factor", 1.0}}, json{{"blow_up_factor", "10"}}, json{{"blow_up_check", 1}},
        json{{"blow_up_check", false}, {"blow_up_factor", 100}}}) {
    json doc = two_bar("dgmpm", 1.0);
    doc["time"].update(bad);
    BOOST_TEST_CONTEXT(bad.dump()) {
      BOOST_CHECK_THROW(scene::parse_scene(doc), scene::SceneError);
      try {
        scene::parse_scene(doc);
      } catch (const scene::SceneError& e) {
        BOOST_TEST(std::string(e.what()).find("time.blow_up_") != std::string::npos);
      }
    }
  }
}

// With the growth check off, the states overflow: the run stops at the first step with a
// non-finite particle state (DGMPM checks the states as its last stage writes them), naming the
// particle and its cell, before the end time and without writing further.
BOOST_AUTO_TEST_CASE(a_non_finite_state_stops_the_run) {
  for (const auto& [method, integrator] :
       {std::pair{"dgmpm", "euler"}, std::pair{"dgmpm", "rk2"}, std::pair{"mpm-usl", "euler"}}) {
    BOOST_TEST_CONTEXT(method << ' ' << integrator) {
      json doc = two_bar(method, method == std::string("dgmpm") ? 1.5 : 1.0);
      doc["time"]["integrator"] = integrator;
      doc["time"]["blow_up_check"] = false;
      doc["time"]["end"] = 1.0;
      const std::string what = failure(doc);
      BOOST_TEST(what.find("non-finite state on particle") != std::string::npos, what);
      BOOST_TEST(what.find(", cell ") != std::string::npos, what);
      const long step = step_of(what);
      BOOST_TEST(step > 10);
      // The step before it was finite: the same scene stopped one step earlier ends finite.
      BarSimulation sim(scene::parse_scene(doc));
      for (long k = 1; k < step; ++k) sim.step(sim.stable_time_step());
      BOOST_TEST(sim.stress().allFinite());
      BOOST_TEST(sim.velocity().allFinite());
    }
  }
}
