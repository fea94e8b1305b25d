// Inputs accepted alone but wrong together, or at the edge of the double range: refused before
// any step with the key path (and, for the JSON text, line and column), or computed without
// overflow.
#define BOOST_TEST_MODULE solver_extreme_inputs
#include <boost/test/unit_test.hpp>

#include "common/scratch.hpp"

#include "solver/problem.hpp"
#include "solver/scene.hpp"
#include "solver/simulation.hpp"
#include <stability/admissible_courant.hpp>

#include <nlohmann/json.hpp>

#include <cmath>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <string>

using namespace dgmpm;
using nlohmann::json;

namespace {

json bar(json layout = {{"particles_per_cell", 1}}) {
  json body = {
      {"material", "steel"}, {"box", {{"min", {0.0}}, {"max", {1.0}}}}, {"velocity", {1.0}}};
  body.update(layout);
  return {{"dimension", 1},
          {"grid", {{"origin", {0.0}}, {"cell_size", {0.1}}, {"cells", {10}}}},
          {"materials", {{"steel", {{"young", 2e11}, {"density", 7800}}}}},
          {"bodies", {body}},
          {"time", {{"end", 1e-4}, {"courant", 1.0}}}};
}

std::string refusal_of_text(const std::string& text) {
  const auto path = dgmpm::test::scratch() / "extreme_input.json";
  std::ofstream(path, std::ios::binary) << text;
  try {
    scene::load_scene(path.string());
  } catch (const scene::SceneError& e) {
    std::filesystem::remove(path);
    return e.what();
  }
  std::filesystem::remove(path);
  return "";
}

std::string refusal(const json& doc) {
  try {
    scene::parse_scene(doc);
  } catch (const scene::SceneError& e) {
    return e.what();
  }
  return "";
}

}  // namespace

// Relative weights at the top of the double range: normalised before they are summed.
BOOST_AUTO_TEST_CASE(huge_relative_masses_do_not_overflow) {
  const auto masses = [](double w) {
    const auto p = make_problem<ElasticBar>(
        scene::parse_scene(bar({{"particles_per_cell", 2}, {"masses_in_cell", {w, 3 * w}}})));
    return p.particles.mass;
  };
  const Eigen::VectorXd unit = masses(1.0), huge = masses(1e308 / 3);
  BOOST_TEST((unit - huge).cwiseAbs().maxCoeff() <= 1e-12 * unit.maxCoeff());
  BOOST_TEST(unit.sum() == 7800 * 1.0, boost::test_tools::tolerance(1e-12));
  const auto courant = [](double w) {
    return stability::admissible_courant({{0.25, 0.75}, {w, w}}, stability::TimeScheme::euler,
                                         stability::Criterion::l2)
        .courant;
  };
  BOOST_TEST(courant(1e308) == courant(1.0));
  BOOST_TEST(courant(1e-308) == courant(1.0));
}

// The JSON text: a number too large for a double, a syntax error, a NUL in a key.
BOOST_AUTO_TEST_CASE(json_errors_name_key_line_and_column) {
  const std::string overflow = refusal_of_text("{\"dimension\": 1,\n \"time\": {\"end\": 1e309}}");
  BOOST_TEST(overflow.find("time.end: invalid JSON (line 2, column 18)") != std::string::npos,
             overflow);
  BOOST_TEST(overflow.find("1e309 is too large for a double") != std::string::npos);
  const std::string syntax = refusal_of_text("{\"dimension\": 1,\n \"time\": {\"end\": 1,}}");
  BOOST_TEST(syntax.find("(line 2, column 20)") != std::string::npos, syntax);
  const std::string nul = refusal_of_text(std::string("{\"ti\\u0000me\": 1}"));
  BOOST_TEST(nul.find("ti\\u0000me: unknown key; allowed keys: dimension") != std::string::npos,
             nul);
}

// Values valid alone whose physics leaves the double range: refused with the key responsible.
BOOST_AUTO_TEST_CASE(physics_outside_the_double_range_is_refused) {
  struct Case {
    const char* key;
    json (*edit)(json);
  };
  const Case cases[] = {
      {"materials.steel:", [](json d) { return d["materials"]["steel"]["young"] = 1e308, d; }},
      {"materials.steel:", [](json d) { return d["materials"]["steel"]["density"] = 1e-308, d; }},
      {"bodies[0].velocity:", [](json d) { return d["bodies"][0]["velocity"] = {1e308}, d; }},
      {"grid.cell_size:",
       [](json d) {
         d["grid"]["cell_size"] = {1e-320};
         d["bodies"][0]["box"]["max"] = {5e-320};
         return d;
       }},
  };
  for (const Case& c : cases) {
    const std::string what = refusal(c.edit(bar()));
    BOOST_TEST(what.find(c.key) != std::string::npos, what);
    BOOST_TEST(what.find("double") != std::string::npos, what);
  }
  BOOST_TEST(refusal(bar()).empty());  // and the plain scene is accepted
}

// An end time needing more steps than time.max_steps (default 1e7) is refused up front with the
// estimate; exactly max_steps steps run.
BOOST_AUTO_TEST_CASE(runs_longer_than_max_steps_are_refused_up_front) {
  json doc = bar();
  doc["time"]["end"] = 1e308;
  const auto run = [](const json& d) -> std::string {
    try {
      scene::Scene s = scene::parse_scene(d);
      with_physics(s,
                   [&](auto physics) { Simulation<typename decltype(physics)::type>(s).run({}); });
    } catch (const scene::SceneError& e) {
      return e.what();
    }
    return "";
  };
  const std::string what = run(doc);
  BOOST_TEST(what.find("time.end: value 1e+308 needs about") != std::string::npos, what);
  BOOST_TEST(what.find("more than time.max_steps (10000000)") != std::string::npos, what);
  const double dt = 0.1 / std::sqrt(2e11 / 7800);
  doc["time"]["end"] = 80 * dt;
  doc["time"]["max_steps"] = 80;
  BOOST_TEST(run(doc).empty());
  doc["time"]["max_steps"] = 79;
  BOOST_TEST(run(doc).find("more than time.max_steps (79)") != std::string::npos);
  doc["time"]["max_steps"] = 0.5;
  BOOST_TEST(refusal(doc).find("time.max_steps") != std::string::npos);
}

// Resources: a scene that cannot fit in memory is refused before anything is allocated, with
// the estimate; node counts beyond an int are refused; only regular files are read.
BOOST_AUTO_TEST_CASE(resources_are_checked_before_use) {
  json doc = bar();
  doc["grid"]["cells"] = {1000000000};
  doc["grid"]["cell_size"] = {1e-9};
  const auto problem_refusal = [](const json& d) -> std::string {
    try {
      make_problem<ElasticBar>(scene::parse_scene(d));
    } catch (const scene::SceneError& e) {
      return e.what();
    }
    return "";
  };
  const std::string big = problem_refusal(doc);
  BOOST_TEST(big.find("bodies: 1e+09 particles on 1e+09 cells need about") != std::string::npos,
             big);
  doc["grid"]["cells"] = {2147483647};
  const std::string nodes = refusal(doc);
  BOOST_TEST(nodes.find("grid.cells: value [2147483647] makes 4294967294 nodes") !=
                 std::string::npos,
             nodes);
  for (const char* device : {"/dev/zero", "/dev/null"}) {
    std::string what;
    try {
      scene::load_scene(device);
    } catch (const scene::SceneError& e) {
      what = e.what();
    }
    BOOST_TEST(what.find("not a regular file") != std::string::npos, device << ": " << what);
  }
}

// Validation is n log n in the output times and the bodies (it was quadratic: 22 s for 200 000
// times, 13 s for 2000 bodies): a repeated time is found at its second index, an overlap between
// the right pair among 2000 bodies.
BOOST_AUTO_TEST_CASE(large_lists_are_validated) {
  json doc = bar();
  doc["time"]["end"] = 1.0;
  json times = json::array();
  for (int k = 1; k <= 200000; ++k) times.push_back(k * 1e-6);
  doc["output"] = {{"times", times}};
  BOOST_TEST(refusal(doc).empty());
  doc["output"]["times"][150000] = 7e-6;
  BOOST_TEST(refusal(doc).find("output.times[150000]: value 7e-06 is listed twice") !=
                 std::string::npos,
             refusal(doc));
  json bodies = json::array();
  for (int k = 0; k < 2000; ++k)
    bodies.push_back({{"material", "steel"},
                      {"box", {{"min", {k * 0.1}}, {"max", {(k + 1) * 0.1}}}},
                      {"velocity", {0.0}},
                      {"particles_per_cell", 1}});
  json many = bar();
  many["grid"]["cells"] = {2000};
  many["bodies"] = bodies;
  BOOST_TEST(refusal(many).empty());
  many["bodies"][1500]["box"]["max"] = {150.25};
  BOOST_TEST(refusal(many).find("bodies[1501].box: value") != std::string::npos, refusal(many));
  BOOST_TEST(refusal(many).find("overlaps bodies[1500].box") != std::string::npos);
}
