// Every JSON scene shown in README.md parses and runs (a few steps, nothing written), and its
// loads act on the body (a load on a side the body does not reach would do no work).
#define BOOST_TEST_MODULE solver_docs
#include <boost/test/unit_test.hpp>

#include <solver/scene.hpp>
#include <solver/simulation.hpp>

#include <nlohmann/json.hpp>

#include <fstream>
#include <sstream>
#include <string>
#include <vector>

using namespace dgmpm;

namespace {

std::vector<std::string> json_blocks(const std::string& path) {
  std::ifstream in(path);
  std::stringstream text;
  text << in.rdbuf();
  const std::string s = text.str();
  std::vector<std::string> blocks;
  const std::string open = "```json\n", close = "```";
  for (std::size_t at = s.find(open); at != std::string::npos; at = s.find(open, at)) {
    const std::size_t start = at + open.size(), end = s.find(close, start);
    blocks.push_back(s.substr(start, end - start));
    at = end;
  }
  return blocks;
}

template <class Physics>
void run_briefly(const scene::Scene& scene, bool loaded) {
  Simulation<Physics> sim(scene);
  const double e0 = sim.energy();
  for (int k = 0; k < 20; ++k) sim.step(sim.stable_time_step());
  BOOST_TEST(sim.physical_state().allFinite());
  // Something happens: the bodies move or the loads do work.
  BOOST_TEST((e0 > 0 || sim.energy() > 0));
  if (loaded && scene.method == scene::Method::dgmpm) BOOST_TEST(sim.boundary_work() != 0.0);
}

}  // namespace

BOOST_AUTO_TEST_CASE(readme_scenes_parse_and_run) {
  const auto blocks = json_blocks(std::string(DGMPM_TEST_SOURCE_DIR) + "/README.md");
  BOOST_TEST_REQUIRE(blocks.size() >= 2u);
  for (std::size_t k = 0; k < blocks.size(); ++k) {
    BOOST_TEST_CONTEXT("README json block " << k) {
      nlohmann::json doc = nlohmann::json::parse(blocks[k]);
      doc.erase("output");  // nothing written by the test
      const scene::Scene scene = scene::parse_scene(doc, "README");
      const std::string sides = doc.value("boundaries", nlohmann::json::object()).dump();
      const bool loaded = sides.find("traction") != std::string::npos ||
                          sides.find("velocity") != std::string::npos;
      with_physics(scene, [&](auto physics) {
        run_briefly<typename decltype(physics)::type>(scene, loaded);
      });
    }
  }
}
