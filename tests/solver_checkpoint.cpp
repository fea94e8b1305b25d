// Checkpoints: a run restarted from any of its checkpoints ends bit for bit as the uninterrupted
// run (every output file byte for byte, the summary's numbers exactly), in 1D and 2D, with fixed
// and moving particles, fixed and automatic time steps, DGMPM and MPM; checkpoints of another
// scene or version, or damaged ones, are refused with the reason.
#define BOOST_TEST_MODULE solver_checkpoint
#include <boost/test/unit_test.hpp>

#include "common/scratch.hpp"

#include "solver/checkpoint.hpp"
#include "solver/scene.hpp"
#include "solver/simulation.hpp"

#include <nlohmann/json.hpp>

#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <set>
#include <sstream>
#include <string>
#include <sys/wait.h>
#include <tuple>

using namespace dgmpm;
using nlohmann::json;
namespace fs = std::filesystem;

namespace {

// Its own folder, removed when every case passed (tests/common/scratch.hpp).
const fs::path& root() {
  return dgmpm::test::scratch();
}

std::string read_file(const fs::path& p) {
  std::ifstream in(p, std::ios::binary);
  std::ostringstream s;
  s << in.rdbuf();
  return s.str();
}

std::string write_scene(const std::string& name, const json& doc) {
  fs::create_directories(root());
  const fs::path path = root() / (name + ".json");
  std::ofstream(path) << doc.dump(1);
  return path.string();
}

json bar_1d(const std::string& method, bool move, const std::string& integrator,
            const json& courant) {
  return {{"dimension", 1},
          {"method", method},
          {"grid", {{"origin", {0.0}}, {"cell_size", {0.1}}, {"cells", {16}}}},
          {"materials", {{"steel", {{"young", 2e11}, {"density", 7800}}}}},
          {"bodies",
           {{{"material", "steel"},
             {"box", {{"min", {0.0}}, {"max", {1.0}}}},
             {"velocity", {20.0}},
             {"particles_per_cell", 2},
             {"masses_in_cell", {1.0, 2.0}}}}},
          {"boundaries",
           {{"xmin", {{"type", "traction"}, {"value", {{0.0, 0.0}, {1e-4, -1e8}, {1.0, -1e8}}}}},
            {"xmax", {{"type", "free"}}}}},
          {"time", {{"end", 3e-4}, {"integrator", integrator}, {"courant", courant}}},
          {"particles_move", move},
          {"output", {{"times", {5e-5, 1e-4, 2.2e-4, 3e-4}}}}};
}

json plate_2d(const std::string& method, bool move, const std::string& integrator,
              const std::string& flux, const json& courant) {
  json doc = {{"dimension", 2},
              {"method", method},
              {"grid", {{"origin", {0.0, 0.0}}, {"cell_size", {0.2, 0.2}}, {"cells", {7, 5}}}},
              {"materials", {{"steel", {{"young", 2e11}, {"poisson", 0.3}, {"density", 7800}}}}},
              {"bodies",
               {{{"material", "steel"},
                 {"box", {{"min", {0.0, 0.0}}, {"max", {1.2, 0.8}}}},
                 {"velocity", {5.0, -2.0}},
                 {"particles_per_cell", {1, 1}}}}},
              {"boundaries",
               {{"xmin", {{{"type", "traction"}, {"value", {-2e8, 0.0}}, {"range", {0.0, 0.4}}}}},
                {"ymin", {{"type", "roller"}}}}},
              {"time", {{"end", 6e-4}, {"integrator", integrator}, {"courant", courant}}},
              {"particles_move", move},
              {"output", {{"times", {5e-5, 1.5e-4, 4e-4}}, {"formats", {"csv", "vtu"}}}}};
  if (method == "dgmpm") doc["flux"] = flux;
  return doc;
}

RunSummary run_into(const scene::Scene& scene, const fs::path& dir, RunOptions options = {},
                    const std::string& restart = "") {
  auto sim = make_simulation(scene);
  if (!restart.empty()) sim->restore(restart);
  options.output_directory = dir.string();
  return sim->run(options);
}

// The summary's numbers (what a run computed, not where or how long), printed with the digits
// that give each double back exactly.
std::string numbers(const RunSummary& s) {
  json j = s.to_json();
  for (const char* k :
       {"wall_seconds", "setup_seconds", "stepping_seconds", "time_step_seconds",
        "layout_analysis_seconds", "files", "restarted_from", "warnings", "layouts_analysed"})
    j.erase(k);
  return j.dump();
}

// Output files but the manifest, the summary (compared by numbers) and the checkpoints.
std::set<std::string> outputs(const fs::path& dir) {
  std::set<std::string> names;
  for (const auto& e : fs::directory_iterator(dir)) {
    const std::string n = e.path().filename().string();
    if (n == "manifest.json" || n == "summary.json" || n == ".dgmpm.lock" ||
        e.path().extension() == ".ckpt")
      continue;
    names.insert(n);
  }
  return names;
}

void expect_same_outputs(const fs::path& a, const fs::path& b, const std::string& what) {
  const auto names = outputs(a);
  BOOST_TEST_REQUIRE(names.size() >= 3u);
  BOOST_TEST((names == outputs(b)), what << ": the same files");
  for (const auto& n : names)
    BOOST_TEST((read_file(a / n) == read_file(b / n)), what << ": " << n << " byte for byte");
}

std::vector<fs::path> checkpoints_in(const fs::path& dir) {
  std::vector<fs::path> found;
  for (const auto& e : fs::directory_iterator(dir))
    if (e.path().extension() == ".ckpt") found.push_back(e.path());
  std::sort(found.begin(), found.end());
  return found;
}

// Uninterrupted run, run with checkpoints (unchanged by them), and a restart from each
// checkpoint in a copy of the checkpointing run's directory: all end identical.
void check_restarts(const std::string& name, const json& doc, RunOptions options,
                    std::size_t min_checkpoints = 2) {
  const scene::Scene scene = scene::load_scene(write_scene(name, doc));
  const fs::path a = root() / (name + "_whole"), b = root() / (name + "_checkpointed");
  fs::remove_all(a);
  fs::remove_all(b);
  const std::string whole = numbers(run_into(scene, a));
  BOOST_TEST((numbers(run_into(scene, b, options)) == whole),
             name << ": checkpoints change nothing");
  expect_same_outputs(a, b, name + " (checkpointing run)");
  const auto found = checkpoints_in(b);
  BOOST_TEST_REQUIRE(found.size() >= min_checkpoints,
                     name << ": " << found.size() << " checkpoints");
  for (const auto& ckpt : found) {
    const fs::path c = root() / (name + "_restarted");
    fs::remove_all(c);
    fs::copy(b, c, fs::copy_options::recursive);
    const RunSummary s = run_into(scene, c, {}, (c / ckpt.filename()).string());
    const std::string what = name + " restarted from " + ckpt.filename().string();
    BOOST_TEST((numbers(s) == whole), what << ": summary\n" << numbers(s) << "\n" << whole);
    BOOST_TEST(s.warnings.size() == run_into(scene, root() / "scratch").warnings.size(), what);
    fs::remove_all(root() / "scratch");
    expect_same_outputs(a, c, what);
  }
}

RunOptions every(long steps, double seconds = 0) {
  RunOptions o;
  o.checkpoint_steps = steps;
  o.checkpoint_seconds = seconds;
  return o;
}

std::string refusal(const scene::Scene& scene, const std::string& checkpoint) {
  try {
    make_simulation(scene)->restore(checkpoint);
  } catch (const scene::SceneError& e) {
    return e.what();
  }
  return "";
}

}  // namespace

BOOST_AUTO_TEST_CASE(dgmpm_1d_fixed_particles_automatic_step) {
  check_restarts("bar_euler_auto", bar_1d("dgmpm", false, "euler", "auto"), every(7));
}

BOOST_AUTO_TEST_CASE(dgmpm_1d_moving_particles_rk2_automatic_step) {
  check_restarts("bar_rk2_moving", bar_1d("dgmpm", true, "rk2", "auto"), every(9));
}

BOOST_AUTO_TEST_CASE(dgmpm_1d_checkpoints_in_simulated_time_keep_the_newest) {
  check_restarts("bar_time", bar_1d("dgmpm", true, "euler", 0.8), every(0, 7e-5));
  // With a limit, only the newest are kept, and the manifest lists exactly those.
  const scene::Scene scene =
      scene::load_scene(write_scene("bar_keep", bar_1d("dgmpm", false, "euler", 0.8)));
  const fs::path d = root() / "bar_keep";
  fs::remove_all(d);
  RunOptions o = every(3);
  o.checkpoint_keep = 2;
  run_into(scene, d, o);
  const auto kept = checkpoints_in(d);
  BOOST_TEST_REQUIRE(kept.size() == 2u);
  const json manifest = json::parse(read_file(d / "manifest.json"));
  std::set<std::string> listed;
  for (const auto& f : manifest["files"]) listed.insert(f.get<std::string>());
  for (const auto& k : kept) BOOST_TEST(listed.count(k.filename().string()) == 1u);
  BOOST_TEST(listed.size() == outputs(d).size() + 1 + kept.size());  // + summary.json
}

BOOST_AUTO_TEST_CASE(dgmpm_2d_fixed_particles_rk2_dcu_automatic_step) {
  check_restarts("plate_rk2_auto", plate_2d("dgmpm", false, "rk2", "dcu", "auto"), every(5));
}

BOOST_AUTO_TEST_CASE(dgmpm_2d_moving_particles_euler_ctu_automatic_step) {
  check_restarts("plate_ctu_moving", plate_2d("dgmpm", true, "euler", "ctu", "auto"), every(6));
}

BOOST_AUTO_TEST_CASE(mpm_1d_and_2d) {
  check_restarts("bar_usl", bar_1d("mpm-usl", false, "euler", 0.5), every(11));
  check_restarts("plate_musl_moving", plate_2d("mpm-musl", true, "euler", "dcu", 0.5), every(8));
}

// Materials that yield carry internal variables (plastic strain, hardening, dissipation): in the
// checkpoint, restored bit for bit (the CSV outputs hold them), 1D and 2D, DGMPM and MPM.
BOOST_AUTO_TEST_CASE(plastic_bar_dgmpm_and_mpm) {
  const json steel = {{"model", "elasto_viscoplastic"},
                      {"young", 2e11},
                      {"density", 7800},
                      {"yield_stress", 5e7},
                      {"isotropic_hardening", 1e9},
                      {"kinematic_hardening", 2e9},
                      {"relaxation_time", 1e-6},
                      {"rate_exponent", 3}};
  for (const auto& [name, doc, steps] :
       {std::tuple{"plastic_bar_rk2_moving", bar_1d("dgmpm", true, "rk2", "auto"), 9},
        std::tuple{"plastic_bar_usl", bar_1d("mpm-usl", false, "euler", 0.5), 11}}) {
    json plastic = doc;
    plastic["materials"]["steel"] = steel;
    plastic["bodies"][0]["stress"] = {-1.2e8};  // above the yield stress: it flows from the start
    check_restarts(name, plastic, every(steps));
    const RunSummary s = run_into(scene::load_scene(write_scene(name, plastic)),
                                  root() / (std::string(name) + "_flow"));
    BOOST_TEST(s.energy_dissipated.value_or(0) > 0, name << ": the bar yields");
  }
  // Plane strain: the plate's steel yields under its load.
  json plate_steel = steel;
  plate_steel["poisson"] = 0.3;
  for (const auto& [name, doc, steps] :
       {std::tuple{"plastic_plate_rk2_moving", plate_2d("dgmpm", true, "rk2", "dcu", "auto"), 5},
        std::tuple{"plastic_plate_musl", plate_2d("mpm-musl", false, "euler", "dcu", 0.5), 8}}) {
    json plastic = doc;
    plastic["materials"]["steel"] = plate_steel;
    check_restarts(name, plastic, every(steps));
    const RunSummary s = run_into(scene::load_scene(write_scene(name, plastic)),
                                  root() / (std::string(name) + "_flow"));
    BOOST_TEST(s.energy_dissipated.value_or(0) > 0, name << ": the plate yields");
  }
}

// Finite strain: the displacement (an internal variable), the step that changes with the speeds
// and the Courant range run so far, restored bit for bit; SVK under a tension load (RK2) and the
// neo-Hookean impact (Euler), automatic and fixed steps.
BOOST_AUTO_TEST_CASE(finite_strain_bars) {
  const auto shipped = [](const std::string& name) {
    std::ifstream in(std::string(DGMPM_TEST_SOURCE_DIR) + "/scenes/" + name + ".json");
    json doc = json::parse(in);
    doc["grid"]["cells"] = {60};
    doc["grid"]["cell_size"] = {0.1};
    doc["time"]["end"] = 3e-4;
    doc["output"]["times"] = {1e-4, 2e-4, 3e-4};
    doc["output"]["formats"] = {"csv", "vtu"};
    return doc;
  };
  json svk = shipped("svk_shock_20gpa");
  svk["time"]["integrator"] = "rk2";
  check_restarts("svk_rk2_auto", svk, every(6));
  json nh = shipped("neo_hookean_impact");
  nh["time"]["courant"] = 0.85;
  check_restarts("neo_hookean_fixed", nh, every(7));
  svk["method"] = "mpm-usl";
  svk["time"]["courant"] = 0.5;
  check_restarts("svk_mpm_usl", svk, every(9));
}

// 2D finite strain: the plate pressed by 30 GPa (neo-Hookean, CTU, Euler, automatic step) and the
// strip pulled hard (SVK, DCU, RK2, fixed Courant number), restored bit for bit.
BOOST_AUTO_TEST_CASE(finite_strain_plates) {
  const auto shipped = [](const std::string& name) {
    std::ifstream in(std::string(DGMPM_TEST_SOURCE_DIR) + "/scenes/" + name + ".json");
    json doc = json::parse(in);
    doc["output"]["formats"] = {"csv", "vtu"};
    return doc;
  };
  json plate = shipped("plate_finite_strain");
  plate["grid"]["cells"] = {40, 20};
  plate["grid"]["cell_size"] = {0.01, 0.01};
  plate["time"]["end"] = 3e-5;
  plate["output"]["times"] = {1e-5, 2e-5, 3e-5};
  plate["flux"] = "ctu";
  check_restarts("plate_finite_strain_ctu_auto", plate, every(8));
  json strip = shipped("neo_hookean_strip");
  strip["materials"]["steel"]["model"] = "saint_venant_kirchhoff";
  strip["boundaries"]["xmin"] = {{"type", "traction"}, {"value", {2e10, 1e9}}};
  strip["time"]["integrator"] = "rk2";
  strip["time"]["courant"] = 0.8;
  strip["time"]["end"] = 2e-4;
  strip["output"]["times"] = {1e-4, 2e-4};
  check_restarts("svk_strip_rk2_fixed", strip, every(7));
}

BOOST_AUTO_TEST_CASE(energy_history_cut_back_to_the_checkpoint) {
  // A run killed after its last checkpoint leaves rows (maybe half a row) beyond it: cut away.
  const json doc = bar_1d("dgmpm", false, "euler", 0.5);
  const scene::Scene scene = scene::load_scene(write_scene("bar_cut", doc));
  const fs::path a = root() / "bar_cut_whole", b = root() / "bar_cut";
  fs::remove_all(a);
  fs::remove_all(b);
  run_into(scene, a);
  run_into(scene, b, every(5));
  std::ofstream(b / "energy.csv", std::ios::app) << "999,1.5,0.25,7,8";
  const auto found = checkpoints_in(b);
  BOOST_TEST_REQUIRE(found.size() >= 2u);
  const RunSummary s = run_into(scene, b, {}, found[1].string());
  BOOST_TEST(s.warnings.empty());
  expect_same_outputs(a, b, "after a cut");

  // A history that is not the checkpoint's is started again at the checkpoint's step, and said.
  std::ofstream(b / "energy.csv") << "step,time\n";
  const RunSummary t = run_into(scene, b, {}, found[0].string());
  BOOST_TEST_REQUIRE(t.warnings.size() == 1u);
  BOOST_TEST(t.warnings[0].find("restarts at step") != std::string::npos, t.warnings[0]);
  const std::string history = read_file(b / "energy.csv");
  BOOST_TEST(history.find("\n0,0,") == std::string::npos,
             "no step 0 row: " << history.substr(0, 200));
  const json header = checkpoint::read(found[0].string()).header;
  std::string next_row = "\n";  // built in steps: GCC 12 warns (-Wrestrict) on "\n" + string&&
  next_row += std::to_string(header["step"].get<long>() + 1);
  next_row += ',';
  BOOST_TEST(history.find(next_row) != std::string::npos);
}

BOOST_AUTO_TEST_CASE(restart_into_another_directory_is_said) {
  const scene::Scene scene =
      scene::load_scene(write_scene("bar_move_dir", bar_1d("dgmpm", false, "euler", 0.5)));
  const fs::path a = root() / "bar_move_dir_whole", b = root() / "bar_move_dir",
                 c = root() / "bar_elsewhere";
  fs::remove_all(a);
  fs::remove_all(b);
  fs::remove_all(c);
  run_into(scene, a);
  run_into(scene, b, every(5));
  const auto found = checkpoints_in(b);
  BOOST_TEST_REQUIRE(!found.empty());
  const RunSummary s = run_into(scene, c, {}, found[0].string());
  bool said = false;
  for (const auto& w : s.warnings) said |= w.find("into another directory") != std::string::npos;
  BOOST_TEST(said);
  BOOST_TEST((read_file(a / "particles_003.csv") == read_file(c / "particles_003.csv")));
}

BOOST_AUTO_TEST_CASE(checkpoints_of_another_scene_version_or_damaged_are_refused) {
  json doc = bar_1d("dgmpm", false, "euler", 0.5);
  const scene::Scene scene = scene::load_scene(write_scene("bar_refuse", doc));
  const fs::path b = root() / "bar_refuse";
  fs::remove_all(b);
  run_into(scene, b, every(10));
  const std::string ckpt = checkpoints_in(b).at(0).string();

  // The output directory may change, and the end time to a later one (the run is extended);
  // nothing else.
  json moved = doc;
  moved["output"]["directory"] = (root() / "elsewhere").string();
  BOOST_TEST(refusal(scene::load_scene(write_scene("bar_refuse_dir", moved)), ckpt) == "");
  json longer = doc;
  longer["time"]["end"] = 4e-4;
  BOOST_TEST(refusal(scene::load_scene(write_scene("bar_refuse_end", longer)), ckpt) == "");
  json faster = doc;
  faster["time"]["courant"] = 0.6;
  const std::string other =
      refusal(scene::load_scene(write_scene("bar_refuse_courant", faster)), ckpt);
  BOOST_TEST(other.find("another scene") != std::string::npos, other);
  BOOST_TEST(other.find("/time/courant") != std::string::npos, other);
  const std::string two_d = refusal(
      scene::load_scene(write_scene("plate_refuse", plate_2d("dgmpm", false, "euler", "dcu", 1.0))),
      ckpt);
  BOOST_TEST(two_d.find("another scene") != std::string::npos, two_d);

  // Another version: a checkpoint rewritten with another version string.
  checkpoint::File file = checkpoint::read(ckpt);
  file.header["version"] = "0.0.1";
  const std::string old_version = (root() / "old_version.ckpt").string();
  checkpoint::write(old_version, file);
  const std::string v = refusal(scene, old_version);
  BOOST_TEST(v.find("written by dgmpm 0.0.1") != std::string::npos, v);

  // Damaged: one byte changed, cut short, not a checkpoint at all.
  std::string bytes = read_file(ckpt);
  const fs::path damaged = root() / "damaged.ckpt";
  bytes[bytes.size() / 2] ^= 0x20;
  std::ofstream(damaged, std::ios::binary) << bytes;
  BOOST_TEST(refusal(scene, damaged.string()).find("corrupt") != std::string::npos);
  std::ofstream(damaged, std::ios::binary) << read_file(ckpt).substr(0, 100);
  BOOST_TEST(refusal(scene, damaged.string()).find("truncated") != std::string::npos);
  const std::string not_one = refusal(scene, scene.source);
  BOOST_TEST(not_one.find("not a dgmpm checkpoint") != std::string::npos, not_one);
}

BOOST_AUTO_TEST_CASE(command_line) {
  const std::string binary = DGMPM_BINARY;
  json doc = bar_1d("dgmpm", false, "rk2", "auto");
  const fs::path a = root() / "cli_whole", b = root() / "cli_checkpointed";
  doc["output"]["directory"] = a.string();
  const std::string scene = write_scene("cli", doc);
  fs::remove_all(a);
  fs::remove_all(b);
  const auto sh = [](const std::string& cmd) {
    const int status =
        std::system((cmd + " >/dev/null 2>" + (root() / "stderr.txt").string()).c_str());
    return WIFEXITED(status) ? WEXITSTATUS(status) : -1;
  };
  BOOST_TEST(sh(binary + " run " + scene) == 0);
  BOOST_TEST(sh(binary + " run " + scene + " --out " + b.string() + " --checkpoint-every 2e-5s") ==
             0);
  const auto found = checkpoints_in(b);
  BOOST_TEST_REQUIRE(found.size() >= 5u);
  // The scene defaults to the checkpoint's.
  BOOST_TEST(sh("cd / && " + binary + " run --restart " + found[2].string() + " --out " +
                b.string()) == 0);
  expect_same_outputs(a, b, "command line restart");
  for (const char* bad : {"0", "-3", "abc", "1e-4x", "s", "2.5", "0s", "nans"}) {
    BOOST_TEST(
        sh(binary + " run " + scene + " --out " + b.string() + " --checkpoint-every " + bad) == 2,
        bad);
    const std::string err = read_file(root() / "stderr.txt");
    BOOST_TEST(err.find("--checkpoint-every") != std::string::npos, err);
  }
  // No directory to write them into.
  json quiet = doc;
  quiet["output"].erase("directory");
  BOOST_TEST(sh(binary + " run " + write_scene("cli_quiet", quiet) + " --checkpoint-every 5") == 2);
  BOOST_TEST(read_file(root() / "stderr.txt").find("output directory") != std::string::npos);
  BOOST_TEST(sh(binary + " run " + scene + " --restart " + scene) == 2);
}
