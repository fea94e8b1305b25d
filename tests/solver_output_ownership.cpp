// A run owns its output directory: the same scene run again replaces exactly its earlier files
// (stale ones included), another scene's outputs are refused unless overwritten, and a directory
// in use by a running run is refused.
#define BOOST_TEST_MODULE solver_output_ownership
#include <boost/test/unit_test.hpp>

#include "common/scratch.hpp"

#include "solver/output.hpp"
#include "solver/scene.hpp"
#include "solver/simulation.hpp"

#include <nlohmann/json.hpp>

#include <bit>
#include <cmath>
#include <cstdint>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <set>
#include <sstream>
#include <string>
#include <sys/wait.h>

using namespace dgmpm;
using nlohmann::json;
namespace fs = std::filesystem;

namespace {

// Its own folder, removed when every case passed (tests/common/scratch.hpp).
const fs::path& root() {
  return dgmpm::test::scratch();
}

std::string write_scene(const std::string& name, std::vector<double> times) {
  json doc = {{"dimension", 1},
              {"grid", {{"origin", {0.0}}, {"cell_size", {0.1}}, {"cells", {10}}}},
              {"materials", {{"steel", {{"young", 2e11}, {"density", 7800}}}}},
              {"bodies",
               {{{"material", "steel"},
                 {"box", {{"min", {0.0}}, {"max", {1.0}}}},
                 {"velocity", {1.0}},
                 {"particles_per_cell", 1}}}},
              {"time", {{"end", 1e-4}, {"courant", 1.0}}},
              {"output", {{"directory", (root() / "out").string()}, {"times", times}}}};
  fs::create_directories(root());
  const fs::path path = root() / name;
  std::ofstream(path) << doc.dump();
  return path.string();
}

std::string run(const std::string& scene, bool overwrite = false) {
  try {
    BarSimulation sim(scene::load_scene(scene));
    RunOptions options;
    options.overwrite = overwrite;
    sim.run(options);
  } catch (const std::exception& e) {
    return e.what();
  }
  return "";
}

std::set<std::string> files() {
  std::set<std::string> names;
  for (const auto& e : fs::directory_iterator(root() / "out"))
    names.insert(e.path().filename().string());
  return names;
}

}  // namespace

BOOST_AUTO_TEST_CASE(a_run_owns_its_directory) {
  const std::string three = write_scene("a.json", {2e-5, 5e-5, 1e-4});
  BOOST_TEST(run(three).empty());
  BOOST_TEST(files().count("particles_002.csv") == 1u);
  // The same scene with fewer outputs: the earlier particles_002.csv is stale and goes.
  write_scene("a.json", {1e-4});
  BOOST_TEST(run(three).empty());
  BOOST_TEST(files().count("particles_002.csv") == 0u);
  BOOST_TEST(files().count("particles_000.csv") == 1u);
  // Files that are not the run's stay.
  std::ofstream(root() / "out" / "notes.txt") << "mine";
  BOOST_TEST(run(three).empty());
  BOOST_TEST(files().count("notes.txt") == 1u);
  // Another scene is refused, unless it overwrites.
  const std::string other = write_scene("b.json", {1e-4});
  const std::string refused = run(other);
  BOOST_TEST(refused.find("holds the outputs of") != std::string::npos, refused);
  BOOST_TEST(refused.find("a.json") != std::string::npos, refused);
  BOOST_TEST(run(other, true).empty());
  const std::string back = run(three);
  BOOST_TEST(back.find("b.json") != std::string::npos, back);
  // dgmpm outputs without a manifest (an unknown run) are not ours to delete.
  fs::remove(root() / "out" / "manifest.json");
  BOOST_TEST(run(three).find("of an unknown run") != std::string::npos);
  BOOST_TEST(run(three, true).empty());
}

BOOST_AUTO_TEST_CASE(a_directory_in_use_is_refused) {
  fs::create_directories(root() / "busy");
  output::DirectoryClaim first((root() / "busy").string(), "x.json", {"energy.csv"}, true);
  std::string what;
  try {
    output::DirectoryClaim second((root() / "busy").string(), "x.json", {"energy.csv"}, true);
  } catch (const std::runtime_error& e) {
    what = e.what();
  }
  BOOST_TEST(what.find("is in use by another running dgmpm run") != std::string::npos, what);
}

// A run killed by SIGTERM (or SIGINT) while it writes leaves no temporary file behind, nor a
// held lock: the same run then starts again.
BOOST_AUTO_TEST_CASE(a_killed_run_leaves_no_temporary_file) {
  fs::remove_all(root() / "out");
  json doc = json::parse(std::ifstream(write_scene("long.json", {1.0})));
  doc["time"]["end"] = 1000.0;  // about 5e7 steps: far longer than the second it is given
  doc["time"]["max_steps"] = 1e12;
  const fs::path scene = root() / "long.json";
  std::ofstream(scene) << doc.dump();
  for (const char* signal : {"TERM", "INT"}) {
    const std::string command = std::string("timeout -s ") + signal + " 1 " + DGMPM_BINARY +
                                " run " + scene.string() + " > /dev/null 2>&1";
    const int status = std::system(command.c_str());
    BOOST_TEST(WEXITSTATUS(status) == 124, signal);  // timeout's code: the run was killed
    int temporaries = 0;
    for (const auto& e : fs::directory_iterator(root() / "out"))
      temporaries += e.path().filename().string().find(".part-") != std::string::npos;
    BOOST_TEST(temporaries == 0, signal);
    BOOST_TEST(files().count("manifest.json") == 1u);
  }
}

// summary.json is exactly the --json object (with the Courant numbers used); each particle CSV
// says its time, and outputs.csv indexes the outputs (index, time, files).
BOOST_AUTO_TEST_CASE(outputs_say_what_and_when) {
  fs::remove_all(root() / "out");
  const std::string scene = write_scene("index.json", {2e-5, 1e-4});
  const fs::path printed = root() / "printed.json";
  const std::string command =
      std::string(DGMPM_BINARY) + " run " + scene + " --json > " + printed.string();
  BOOST_TEST_REQUIRE(std::system(command.c_str()) == 0);
  const json j = json::parse(std::ifstream(printed));
  const json summary = json::parse(std::ifstream(root() / "out" / "summary.json"));
  BOOST_TEST(j == summary);
  BOOST_TEST(j["courant_min"].get<double>() == 1.0, boost::test_tools::tolerance(1e-12));
  BOOST_TEST(j["courant_max"].get<double>() == 1.0, boost::test_tools::tolerance(1e-12));
  BOOST_TEST(j["particles"].get<int>() == 10);
  std::ifstream index(root() / "out" / "outputs.csv");
  std::string line;
  std::getline(index, line);
  BOOST_TEST(line == "index,time,csv,vtu");
  for (int k = 0; k < 2; ++k) {
    BOOST_TEST_REQUIRE(static_cast<bool>(std::getline(index, line)));
    const auto c1 = line.find(','), c2 = line.find(',', c1 + 1), c3 = line.find(',', c2 + 1);
    BOOST_TEST(std::stoi(line.substr(0, c1)) == k);
    const double t = std::stod(line.substr(c1 + 1, c2 - c1 - 1));
    BOOST_TEST(t == (k ? 1e-4 : 2e-5), boost::test_tools::tolerance(1e-12));
    const std::string file = line.substr(c2 + 1, c3 - c2 - 1);
    // The file's time column carries the same time on every row.
    std::ifstream particles(root() / "out" / file);
    std::string header, row;
    std::getline(particles, header);
    BOOST_TEST(header.substr(header.rfind(',') + 1) == "time");
    int rows = 0;
    while (std::getline(particles, row)) {
      BOOST_TEST(std::stod(row.substr(row.rfind(',') + 1)) == t);
      ++rows;
    }
    BOOST_TEST(rows == 10);
  }
}

// Output times change the step sequence when steps land on them (shortened steps); with
// "land": false the steps are those of a run without outputs, bit for bit, and each output is
// written at the step nearest its time.
BOOST_AUTO_TEST_CASE(outputs_without_landing_leave_the_steps_alone) {
  const double dt = 0.1 / std::sqrt(2e11 / 7800);
  const std::vector<double> asked = {2.5 * dt, 7.3 * dt};
  const auto run_with = [&](bool outputs, bool land) {
    fs::remove_all(root() / "out");
    json doc = json::parse(std::ifstream(write_scene("land.json", asked)));
    doc["time"]["end"] = 20 * dt;
    doc["time"]["courant"] = 0.9;  // waves move by fractions of a cell: the answer depends on dt
    if (!outputs) doc.erase("output");
    if (outputs) doc["output"]["land"] = land;
    BarSimulation sim(scene::parse_scene(doc));
    const RunSummary s = sim.run({});
    return std::pair{s.steps, sim.stress()};
  };
  const auto [plain_steps, plain] = run_with(false, true);
  const auto [landed_steps, landed] = run_with(true, true);
  const auto [nearest_steps, nearest] = run_with(true, false);
  BOOST_TEST(landed_steps > plain_steps);  // two shortened steps
  BOOST_TEST(nearest_steps == plain_steps);
  BOOST_TEST((nearest.array() == plain.array()).all());
  BOOST_TEST((landed - plain).cwiseAbs().maxCoeff() > 0.0);
  std::ifstream index(root() / "out" / "outputs.csv");
  std::string line;
  std::getline(index, line);
  for (double t : asked) {
    BOOST_TEST_REQUIRE(static_cast<bool>(std::getline(index, line)));
    const double written = std::stod(line.substr(line.find(',') + 1));
    BOOST_TEST(std::abs(written - t) <= 0.5 * 0.9 * dt * (1 + 1e-12));
  }
}

// The tables' number formatting (std::to_chars) writes what a stream of precision 17 writes:
// checked on awkward values and a million random bit patterns (every finite double is a
// candidate). Files keep their bytes from build to build.
BOOST_AUTO_TEST_CASE(numbers_are_written_as_a_stream_writes_them) {
  std::vector<double> values = {0.0,
                                -0.0,
                                1.0,
                                -1.0,
                                0.1,
                                1.0 / 3.0,
                                1e22,
                                1e23,
                                1e-7,
                                123456789012345678.0,
                                5e-324,
                                2.2250738585072014e-308,
                                1.7976931348623157e308,
                                -2.5e-310,
                                100.0,
                                1e16,
                                1e17};
  std::uint64_t bits = 0x9e3779b97f4a7c15ull;
  for (int k = 0; k < 1000000; ++k) {
    bits ^= bits << 13, bits ^= bits >> 7, bits ^= bits << 17;  // xorshift64
    const double x = std::bit_cast<double>(bits);
    if (std::isfinite(x)) values.push_back(x);
  }
  std::ostringstream streamed, formatted;
  streamed.precision(17);  // as output::write_atomically's files
  for (double x : values) {
    streamed << x << ',';
    output::write_number(formatted, x);
    formatted << ',';
  }
  BOOST_TEST_REQUIRE(values.size() > 900000u);
  BOOST_TEST(formatted.str() == streamed.str());
}
