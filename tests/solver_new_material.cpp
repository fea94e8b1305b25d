// A material added by a test alone (step_counting_plane.hpp: plane strain with an internal
// variable counting its particle's steps): the solver's loop, outputs, checkpoints and the MPM
// baseline take it as they are. Its particles' states equal plane strain's to the bit, its counter
// equals the steps taken, its column reaches the CSV and VTU files under its own name, and a
// restart from a checkpoint carries the counter on.
#define BOOST_TEST_MODULE solver_new_material
#include <boost/test/unit_test.hpp>

#include "common/scratch.hpp"

#include "step_counting_plane.hpp"

#include "solver/problem_impl.hpp"
#include "solver/simulation_impl.hpp"

#include <nlohmann/json.hpp>

#include <filesystem>
#include <fstream>
#include <sstream>
#include <string>

namespace dgmpm {
template class Simulation<testing::StepCountingPlane>;
}

using namespace dgmpm;
using nlohmann::json;
using testing::StepCountingPlane;
namespace fs = std::filesystem;

namespace {

// Its own folder, removed when every case passed (tests/common/scratch.hpp).
const fs::path& root() {
  return dgmpm::test::scratch();
}

// The scene description: a plate of the test material, as plane strain's (model
// "linear_elastic"), loaded on part of a side, with void cells around it.
scene::Scene plate(const std::string& method, const std::string& integrator,
                   const std::string& flux) {
  json doc = {{"dimension", 2},
              {"method", method},
              {"grid", {{"origin", {0.0, 0.0}}, {"cell_size", {0.1, 0.1}}, {"cells", {12, 8}}}},
              {"materials", {{"steel", {{"young", 2e11}, {"poisson", 0.3}, {"density", 7800}}}}},
              {"bodies",
               {{{"material", "steel"},
                 {"box", {{"min", {0.0, 0.0}}, {"max", {1.0, 0.6}}}},
                 {"velocity", {3.0, -1.0}},
                 {"particles_per_cell", {2, 2}}}}},
              {"boundaries",
               {{"xmin", {{{"type", "traction"}, {"value", {-1e8, 0.0}}, {"range", {0.0, 0.3}}}}},
                {"ymin", {{"type", "roller"}}}}},
              {"time", {{"end", 2e-4}, {"integrator", integrator}, {"courant", 0.5}}},
              {"output", {{"times", {1e-4, 2e-4}}, {"formats", {"csv", "vtu"}}}}};
  if (method == "dgmpm") doc["flux"] = flux;
  return scene::parse_scene(doc, "new_material_plate");
}

std::string read_file(const fs::path& p) {
  std::ifstream in(p, std::ios::binary);
  std::ostringstream s;
  s << in.rdbuf();
  return s.str();
}

// Every particle's counter is `steps`; returns how many particles.
int check_counters(const Simulation<StepCountingPlane>& sim, long steps) {
  const auto& z = sim.particles().internal;
  BOOST_TEST_REQUIRE(z.rows() == 1);
  int wrong = 0;
  for (int i = 0; i < z.cols(); ++i) wrong += z(0, i) != static_cast<double>(steps);
  BOOST_TEST(wrong == 0, wrong << " particles did not count " << steps << " steps");
  return static_cast<int>(z.cols());
}

}  // namespace

BOOST_AUTO_TEST_CASE(states_are_plane_strain_s_and_the_counter_counts) {
  for (const char* method : {"dgmpm", "mpm-usl"})
    for (const char* integrator : {"euler", "rk2"})
      for (const char* flux : {"dcu", "ctu"}) {
        if (std::string(method) != "dgmpm" && std::string(integrator) == "rk2") continue;
        if (std::string(method) != "dgmpm" && std::string(flux) == "ctu") continue;
        const scene::Scene s = plate(method, integrator, flux);
        Simulation<StepCountingPlane> counting(s);
        Simulation<PlaneStrain> plain(s);
        BOOST_TEST_REQUIRE(counting.stable_time_step() == plain.stable_time_step());
        counting.advance_to(s.time.end);
        plain.advance_to(s.time.end);
        BOOST_TEST_REQUIRE(counting.steps() == plain.steps());
        BOOST_TEST(counting.steps() > 10);
        const double diff =
            (counting.particles().state - plain.particles().state).cwiseAbs().maxCoeff();
        BOOST_TEST(diff == 0.0, method << ' ' << integrator << ' ' << flux);
        BOOST_TEST(check_counters(counting, counting.steps()) == plain.particles().size());
        BOOST_TEST(counting.energy() == plain.energy());
      }
}

BOOST_AUTO_TEST_CASE(outputs_carry_the_column_and_restarts_carry_the_counter_on) {
  const scene::Scene s = plate("dgmpm", "rk2", "dcu");
  const fs::path whole = root() / "whole", checkpointed = root() / "checkpointed",
                 restarted = root() / "restarted";
  Simulation<StepCountingPlane> a(s);
  RunOptions options;
  options.output_directory = whole.string();
  a.run(options);
  const long steps = a.steps();
  check_counters(a, steps);

  // The last CSV's column holds the counter of the step the output was written at.
  std::ifstream csv(whole / "particles_001.csv");
  std::string header, row;
  std::getline(csv, header);
  std::vector<std::string> names;
  for (std::stringstream h(header); std::getline(h, row, ',');) names.push_back(row);
  const auto column = std::find(names.begin(), names.end(), "steps_taken");
  BOOST_TEST_REQUIRE((column != names.end()), header);
  int rows = 0, wrong = 0;
  while (std::getline(csv, row)) {
    std::stringstream r(row);
    std::string cell;
    for (std::ptrdiff_t k = 0; k <= column - names.begin(); ++k) std::getline(r, cell, ',');
    ++rows;
    wrong += std::stod(cell) != static_cast<double>(steps);
  }
  BOOST_TEST(rows == a.particles().size());
  BOOST_TEST(wrong == 0);
  BOOST_TEST(read_file(whole / "particles_001.vtu").find("Name=\"steps_taken\"") !=
             std::string::npos);

  // Checkpoints every 7 steps; a restart from the first one ends as the whole run, byte for byte.
  Simulation<StepCountingPlane> b(s);
  options.output_directory = checkpointed.string();
  options.checkpoint_steps = 7;
  b.run(options);
  std::vector<fs::path> found;
  for (const auto& e : fs::directory_iterator(checkpointed))
    if (e.path().extension() == ".ckpt") found.push_back(e.path());
  std::sort(found.begin(), found.end());
  BOOST_TEST_REQUIRE(found.size() >= 2u);
  fs::copy(checkpointed, restarted, fs::copy_options::recursive);
  Simulation<StepCountingPlane> c(s);
  c.restore((restarted / found.front().filename()).string());
  BOOST_TEST(c.steps() == 7);
  check_counters(c, 7);
  RunOptions again;
  again.output_directory = restarted.string();
  c.run(again);
  check_counters(c, steps);
  for (const char* f :
       {"particles_000.csv", "particles_001.csv", "particles_001.vtu", "energy.csv"})
    BOOST_TEST((read_file(whole / f) == read_file(restarted / f)), f);
}
