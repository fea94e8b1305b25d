#include "reports/report.hpp"

#include "reports/finite_strain.hpp"
#include "reports/plasticity.hpp"
#include "reports/report_io.hpp"

#include "solver/installation.hpp"

#include "solver/output.hpp"
#include "solver/simulation.hpp"
#include "stability/admissible_courant.hpp"
#include "stability/courant_map.hpp"
#include "stability/layout.hpp"

#include <gsl/gsl_fit.h>
#include <omp.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <ctime>
#include <fstream>
#include <functional>
#include <iomanip>
#include <limits>
#include <map>
#include <ostream>
#include <sstream>
#include <thread>

namespace dgmpm::report {

namespace {

namespace st = stability;

struct Environment {
  std::string commit, build_type, cpu, date, load;
  unsigned cores = 0;
};

Environment environment() {
  Environment e;
  // Recorded at build time (the binary may run far from its sources).
  std::ifstream commit(data_directory() + "/commit.txt");
  if (!std::getline(commit, e.commit) || e.commit.empty()) e.commit = "unknown";
  e.build_type = DGMPM_BUILD_TYPE;
  if (e.build_type.empty()) e.build_type = "unspecified";
  std::ifstream loadavg("/proc/loadavg");
  double l1 = 0, l5 = 0, l15 = 0;
  if (loadavg >> l1 >> l5 >> l15) {
    std::ostringstream s;
    s << l1 << ", " << l5 << ", " << l15;
    e.load = s.str();
  } else {
    e.load = "unknown";
  }
  std::ifstream cpuinfo("/proc/cpuinfo");
  for (std::string line; std::getline(cpuinfo, line);)
    if (line.rfind("model name", 0) == 0) {
      e.cpu = line.substr(line.find(':') + 1);
      e.cpu.erase(0, e.cpu.find_first_not_of(' '));
      break;
    }
  if (e.cpu.empty()) e.cpu = "unknown";
  e.cores = std::thread::hardware_concurrency();
  const std::time_t now = std::time(nullptr);
  char date[64];
  std::strftime(date, sizeof date, "%Y-%m-%d %H:%M:%S UTC", std::gmtime(&now));
  e.date = date;
  return e;
}

// ---- methods -------------------------------------------------------------------------------

struct Method {
  MethodSpec spec;
  std::string family, variant, update, courant_mode;  // CSV columns for plot styles
};

// Every method runs at one realistic Courant number, below every layout's C* (Euler with 8
// particles per cell: 0.62), and DGMPM also at its automatic one (C* = 1 for one particle per
// cell and for RK2: exact transport, round-off errors on the two bars).
constexpr double common_courant = 0.5;
// MPM runs with one particle per cell: USL with 1 ppc is unstable above 1/sqrt(2).
constexpr int mpm_ppc = 1;

std::vector<Method> accuracy_methods() {
  std::vector<Method> methods;
  for (const std::string integrator : {"euler", "rk2"})
    for (int ppc : {1, 2, 4}) {
      const std::string name = std::string("DGMPM ") + (integrator == "euler" ? "Euler " : "RK2 ") +
                               std::to_string(ppc) + "ppc";
      std::ostringstream common;
      common << name << " C=" << common_courant;
      methods.push_back({{common.str(), "dgmpm", "", integrator, ppc, false, common_courant, ""},
                         "dgmpm",
                         integrator,
                         "",
                         "fixed"});
      methods.push_back({{name + " auto", "dgmpm", "", integrator, ppc, true, 1.0, ""},
                         "dgmpm",
                         integrator,
                         "",
                         "auto"});
    }
  for (const std::string variant : {"usl", "usf", "musl"})
    for (const std::string update : {"flip", "pic"}) {
      std::string name = "MPM " + variant + " " + update;
      std::transform(name.begin(), name.end(), name.begin(), ::toupper);
      std::ostringstream label;
      label << name << " " << mpm_ppc << "ppc C=" << common_courant;
      methods.push_back(
          {{label.str(), "mpm-" + variant, update, "euler", mpm_ppc, false, common_courant, ""},
           "mpm",
           variant,
           update,
           "fixed"});
    }
  return methods;
}

std::vector<int> grids(Problem p, bool quick) {
  // Two bars: multiples of 6 cells (body boundary and, at Courant 1, the end time on faces).
  if (p == Problem::two_bar)
    return quick ? std::vector<int>{60, 120, 240, 480, 960}
                 : std::vector<int>{60, 120, 240, 480, 960, 1920, 3840, 7680};
  return quick ? std::vector<int>{50, 100, 200, 400, 800}
               : std::vector<int>{50, 100, 200, 400, 800, 1600, 3200, 6400};
}

// 2D: the P plane wave at 30 degrees (scenes/plane_wave_p_30deg.json, one period on a doubly
// periodic grid) by DGMPM (DCU/CTU x Euler/RK2, at the common Courant number and automatic) and
// MPM (USL/USF/MUSL, FLIP), 1 particle per cell (quick) or 1 and 4.
const char* const plane_wave_problem = "plane_wave_p_30deg";

std::vector<Method> plane_wave_methods(bool quick) {
  std::vector<Method> methods;
  const std::vector<int> counts = quick ? std::vector<int>{1} : std::vector<int>{1, 4};
  for (const std::string flux : {"dcu", "ctu"})
    for (const std::string integrator : {"euler", "rk2"})
      for (int ppc : counts) {
        const std::string name = std::string("DGMPM ") + (flux == "dcu" ? "DCU " : "CTU ") +
                                 (integrator == "euler" ? "Euler " : "RK2 ") + std::to_string(ppc) +
                                 "ppc";
        std::ostringstream common;
        common << name << " C=" << common_courant;
        // Plot colours per flux and integrator.
        const std::string variant = flux + "-" + integrator;
        Method fixed{{common.str(), "dgmpm", "", integrator, ppc, false, common_courant, flux},
                     "dgmpm",
                     variant,
                     "",
                     "fixed"};
        Method automatic{{name + " auto", "dgmpm", "", integrator, ppc, true, 1.0, flux},
                         "dgmpm",
                         variant,
                         "",
                         "auto"};
        methods.push_back(fixed);
        methods.push_back(automatic);
      }
  for (const std::string variant : {"usl", "usf", "musl"}) {
    std::string name = "MPM " + variant + " flip";
    std::transform(name.begin(), name.end(), name.begin(), ::toupper);
    std::ostringstream label;
    label << name << " 1ppc C=" << common_courant;
    methods.push_back(
        {{label.str(), "mpm-" + variant, "flip", "euler", 1, false, common_courant, ""},
         "mpm",
         variant,
         "flip",
         "fixed"});
  }
  return methods;
}

// The full mode reaches grids (up to 256 x 443 cells, 1.1e5 particles at one per cell) where the
// time loop, not the set-up, takes most of the run: the methods' engineering shows in the wall
// time.
std::vector<int> plane_wave_grids(bool quick) {
  return quick ? std::vector<int>{8, 16, 32} : std::vector<int>{8, 16, 32, 64, 128, 256};
}

// `cells` cells along x (and the nearest count along y for square-ish cells), the method's
// particles per cell in both directions, no outputs.
nlohmann::json plane_wave_scene(int cells, const MethodSpec& m) {
  nlohmann::json doc;
  std::ifstream(data_file(std::string("scenes/") + plane_wave_problem + ".json")) >> doc;
  const double lx = doc["bodies"][0]["box"]["max"][0], ly = doc["bodies"][0]["box"]["max"][1];
  const int ny = static_cast<int>(std::lround(cells * ly / lx));
  doc["grid"]["cells"] = {cells, ny};
  doc["grid"]["cell_size"] = {lx / cells, ly / ny};
  doc["bodies"][0]["particles_per_cell"] = {m.particles_per_cell == 4 ? 2 : 1,
                                            m.particles_per_cell == 4 ? 2 : 1};
  doc.erase("output");
  doc.erase("flux");
  apply_method(doc, m);
  if (m.method != "dgmpm") doc["time"].erase("integrator");
  return doc;
}

// ---- convergence fits ----------------------------------------------------------------------

// Errors at round-off carry no order: fits use errors above this.
constexpr double roundoff_error = 1e-12;

OrderFit fit_order(const std::string& problem, const std::string& label,
                   const std::vector<RunRow>& rows) {
  OrderFit f{problem,
             label,
             0,
             std::numeric_limits<double>::quiet_NaN(),
             std::numeric_limits<double>::quiet_NaN(),
             ""};
  std::vector<double> x, y;
  bool any_roundoff = false;
  for (const RunRow& r : rows) {
    if (r.problem != problem || r.label != label || !r.stable) continue;
    if (!(r.l2_error > roundoff_error)) {
      any_roundoff = true;
      continue;
    }
    x.push_back(std::log(r.h));
    y.push_back(std::log(r.l2_error));
  }
  f.points = static_cast<int>(x.size());
  if (x.size() < 2) {
    f.note = any_roundoff ? "round-off error on every grid" : "fewer than 2 stable grids";
    return f;
  }
  double c0, c1, cov00, cov01, cov11, sumsq;
  gsl_fit_linear(x.data(), 1, y.data(), 1, x.size(), &c0, &c1, &cov00, &cov01, &cov11, &sumsq);
  f.intercept = c0;
  f.order = c1;
  return f;
}

// ---- CSV -----------------------------------------------------------------------------------

const char* run_header =
    "problem,label,family,variant,update,integrator,ppc,courant_mode,courant,cells,h,steps,"
    "dt_min,dt_max,wall_seconds,l2_error,max_error,energy_drift,stable,failure\n";

std::string csv_text(std::string s) {
  std::replace(s.begin(), s.end(), ',', ';');
  std::replace(s.begin(), s.end(), '\n', ' ');
  std::replace(s.begin(), s.end(), '"', '\'');
  return s;
}

// Free text inside a Markdown table cell.
std::string markdown_text(std::string s) {
  std::replace(s.begin(), s.end(), '|', '/');
  std::replace(s.begin(), s.end(), '\n', ' ');
  return s;
}

void write_run(std::ostream& out, const RunRow& r, const Method& m) {
  out << r.problem << ',' << r.label << ',' << m.family << ',' << m.variant << ',' << m.update
      << ',' << m.spec.integrator << ',' << m.spec.particles_per_cell << ',' << m.courant_mode
      << ',' << (m.spec.courant_auto ? std::string("auto") : num(m.spec.courant)) << ',' << r.cells
      << ',' << num(r.h) << ',' << r.steps << ',' << num(r.dt_min) << ',' << num(r.dt_max) << ','
      << num(r.wall_seconds) << ',' << num(r.l2_error) << ',' << num(r.max_error) << ','
      << num(r.energy_drift) << ',' << (r.stable ? 1 : 0) << ',' << csv_text(r.failure) << '\n';
}

// ---- stiff and extreme cases ---------------------------------------------------------------

struct StiffCase {
  std::string name;
  nlohmann::json scene;
  double courant_reference;  // wave speed / cell size, to report the Courant number used
};

// Two bars on [0, 3] and [3, 6] in a wider grid (room for moving particles), free ends, ending
// after the bars separate (t = 12 m / c): energy is conserved, so its growth flags instability.
// The margin is a whole number of cells unless `shift` (in cells) moves the bars off the faces.
struct StiffOptions {
  std::string criterion = "l2";
  bool move = false;
  double young_right = 2e11;
  double shift = 0;
  double safety = 1;
  bool paper = false;  // the founding paper's formulation instead of the consistent one
};

StiffCase stiff_case(const std::string& name, int cells_per_metre, nlohmann::json layout,
                     const std::string& integrator, nlohmann::json courant,
                     const StiffOptions& o = {}) {
  const double young = 2e11, density = 7800, c = std::sqrt(young / density);
  const double z = std::sqrt(young * density), v0 = 4e9 / (2 * z), dx = 1.0 / cells_per_metre;
  const int margin = (cells_per_metre + 1) / 2;  // about 0.5 m
  nlohmann::json materials = {{"steel", {{"young", young}, {"density", density}}}};
  std::string right = "steel";
  if (o.young_right != young) {
    right = "soft";
    materials["soft"] = {{"young", o.young_right}, {"density", density}};
  }
  auto body = [&](double lo, double hi, double v, const std::string& material) {
    nlohmann::json b = {
        {"material", material}, {"box", {{"min", {lo}}, {"max", {hi}}}}, {"velocity", {v}}};
    b.update(layout);
    return b;
  };
  nlohmann::json scene = {
      {"dimension", 1},
      {"grid",
       {{"origin", {-(margin + o.shift) * dx}},
        {"cell_size", {dx}},
        {"cells", {6 * cells_per_metre + 2 * margin + 1}}}},
      {"materials", materials},
      {"bodies", {body(0, 3, v0, "steel"), body(3, 6, -v0, right)}},
      {"time", {{"end", 12.0 / c}, {"integrator", integrator}, {"courant", courant}}},
      {"particles_move", o.move}};
  // The table reports which cases blow up and how far: they run to the end.
  scene["time"]["blow_up_check"] = false;
  if (courant.is_string()) scene["time"]["criterion"] = o.criterion;
  if (o.safety != 1) scene["time"]["safety"] = o.safety;
  if (o.paper) scene["formulation"] = "paper";
  if (o.young_right == young) scene["exact"] = "bar";
  return {name, scene, c / dx};
}

std::vector<StiffCase> stiff_cases(bool quick) {
  const int n = quick ? 10 : 25;  // cells per metre
  using J = nlohmann::json;
  const J one = {{"particles_per_cell", 1}}, two = {{"particles_per_cell", 2}},
          eight = {{"particles_per_cell", 8}};
  StiffOptions monotone, soft, moving, moving_monotone, shifted, shifted_safe;
  monotone.criterion = "monotone";
  soft.young_right = 2e9;
  moving.move = true;
  moving_monotone = moving;
  moving_monotone.criterion = "monotone";
  shifted.shift = 0.5;
  shifted_safe = shifted;
  shifted_safe.safety = 0.8;
  StiffOptions shifted_paper = shifted, moving_monotone_paper = moving_monotone,
               moving_paper = moving;
  shifted_paper.paper = moving_monotone_paper.paper = moving_paper.paper = true;
  return {
      stiff_case("1 ppc at cell centres, Euler", n, one, "euler", "auto"),
      stiff_case("1 ppc on the left nodes, Euler", n, {{"positions_in_cell", {0.0}}}, "euler",
                 "auto"),
      stiff_case("2 ppc near the nodes (0.01, 0.99), Euler", n,
                 {{"positions_in_cell", {0.01, 0.99}}}, "euler", "auto"),
      stiff_case("2 ppc, one on a node (0, 0.5), Euler", n, {{"positions_in_cell", {0.0, 0.5}}},
                 "euler", "auto"),
      stiff_case("2 ppc, masses 1:100, Euler", n,
                 {{"positions_in_cell", {0.25, 0.75}}, {"masses_in_cell", {1.0, 100.0}}}, "euler",
                 "auto"),
      stiff_case("8 ppc regular, Euler", n, eight, "euler", "auto"),
      stiff_case("8 ppc regular, RK2", n, eight, "rk2", "auto"),
      stiff_case("8 ppc, bar ends mid-cell (half-full end cells), Euler", n, eight, "euler", "auto",
                 shifted),
      stiff_case("8 ppc, bar ends mid-cell (half-full end cells), RK2", n, eight, "rk2", "auto",
                 shifted),
      stiff_case("8 ppc, bar ends mid-cell (half-full end cells), RK2, safety 0.8", n, eight, "rk2",
                 "auto", shifted_safe),
      stiff_case("8 ppc, bar ends mid-cell (half-full end cells), RK2, paper's formulation", n,
                 eight, "rk2", "auto", shifted_paper),
      stiff_case("2 ppc regular, Euler, monotone criterion", n, two, "euler", "auto", monotone),
      stiff_case("bi-material, E ratio 100, 1 ppc, Euler", n, one, "euler", "auto", soft),
      stiff_case("bi-material, E ratio 100, 2 ppc, RK2", n, two, "rk2", "auto", soft),
      stiff_case("moving particles, 1 ppc, Euler", n, one, "euler", "auto", moving),
      stiff_case("moving particles, 1 ppc, Euler, monotone criterion", n, one, "euler", "auto",
                 moving_monotone),
      stiff_case("moving particles, 1 ppc, Euler, monotone criterion, paper's formulation", n, one,
                 "euler", "auto", moving_monotone_paper),
      stiff_case("moving particles, 2 ppc, Euler", n, two, "euler", "auto", moving),
      stiff_case("moving particles, 2 ppc, Euler, paper's formulation", n, two, "euler", "auto",
                 moving_paper),
      stiff_case("contrast: 2 ppc, Euler, fixed C = 1 > C*", n, two, "euler", 1.0),
  };
}

// ---- plotting ------------------------------------------------------------------------------

// The founding paper's 2D plate (scenes/plate_impact.json) by one method, fields at 5e-4 and
// 1e-3 s written under dir/plate_<tag>.
struct PlateRun {
  const char* tag;
  const char* title;
  const char* method;
  const char* flux;
  const char* integrator;
  double courant;
};

const PlateRun plate_runs[] = {
    {"dgmpm_dcu_rk2", "DGMPM DCU RK2, Courant 1", "dgmpm", "dcu", "rk2", 1.0},
    {"dgmpm_ctu_euler", "DGMPM CTU Euler, Courant 1", "dgmpm", "ctu", "euler", 1.0},
    {"mpm_usf", "MPM USF (FLIP), Courant 0.5", "mpm-usf", "", "", 0.5},
};

double run_plate(const PlateRun& run, const std::string& dir) {
  nlohmann::json doc;
  std::ifstream(data_file("scenes/plate_impact.json")) >> doc;
  doc["method"] = run.method;
  if (std::string(run.method) == "dgmpm") {
    doc["flux"] = run.flux;
    doc["time"]["integrator"] = run.integrator;
  } else {
    doc.erase("flux");
    doc["time"].erase("integrator");
  }
  doc["time"]["courant"] = run.courant;
  doc["output"] = {
      {"directory", dir + "/plate_" + run.tag}, {"times", {5e-4, 1e-3}}, {"formats", {"csv"}}};
  PlaneStrainSimulation sim(scene::parse_scene(doc, std::string("plate ") + run.tag));
  return sim.run().energy_final;
}

// ---- Markdown ------------------------------------------------------------------------------

struct StabilityData {
  std::vector<int> counts;
  // [scheme][criterion][n - 1]
  double regular[2][2][8] = {};
  int map_size = 0;
};

// 2D: C* of one particle over an n x n grid of its positions, for two settings; C* of regular
// layouts for every flux x integrator x (model, criterion).
struct Stability2D {
  struct Panel {
    const char* name;  // for CSV and titles
    st::TimeScheme time;
    FluxScheme flux;
    std::vector<double> courant;  // [j * n + i]: particle at ((i + 1/2) / n, (j + 1/2) / n)
  };
  int map_size = 0;
  std::vector<Panel> panels;
  struct Regular {
    std::string model, criterion, flux, integrator;
    int particles = 0;
    double courant = 0;
  };
  std::vector<Regular> regular;
};

st::CellLayout regular_layout_2d(int per_axis) {
  st::CellLayout layout;
  layout.dim = 2;
  for (int j = 0; j < per_axis; ++j)
    for (int i = 0; i < per_axis; ++i) {
      layout.positions.push_back((i + 0.5) / per_axis);
      layout.positions.push_back((j + 0.5) / per_axis);
    }
  return layout;
}

Stability2D stability_2d(bool quick) {
  Stability2D out;
  out.map_size = quick ? 5 : 9;  // odd: the centre is one of the positions
  const int n = out.map_size;
  out.panels = {{"RK2 DCU", st::TimeScheme::rk2, FluxScheme::dcu, {}},
                {"Euler CTU", st::TimeScheme::euler, FluxScheme::ctu, {}}};
  for (auto& panel : out.panels) {
    st::AnalysisSetting setting;
    setting.dim = 2;
    setting.time = panel.time;
    setting.flux = panel.flux;
    for (int j = 0; j < n; ++j)
      for (int i = 0; i < n; ++i)
        panel.courant.push_back(
            st::admissible_courant(st::CellLayout{{(i + 0.5) / n, (j + 0.5) / n}, {}, 2}, setting,
                                   st::Criterion::l2)
                .courant);
  }
  const std::vector<int> per_axis = quick ? std::vector<int>{1, 2} : std::vector<int>{1, 2, 3};
  for (const auto& [model, criterion] : {std::pair{st::Model::advection, st::Criterion::l2},
                                         std::pair{st::Model::advection, st::Criterion::monotone},
                                         std::pair{st::Model::elastic, st::Criterion::l2}})
    for (FluxScheme flux : {FluxScheme::dcu, FluxScheme::ctu})
      for (st::TimeScheme time : {st::TimeScheme::euler, st::TimeScheme::rk2})
        for (int k : per_axis) {
          st::AnalysisSetting setting;
          setting.dim = 2;
          setting.time = time;
          setting.flux = flux;
          setting.model = model;
          if (model == st::Model::advection) setting.speed_y = 1.0;  // a = b = 1
          out.regular.push_back(
              {st::to_string(model), st::to_string(criterion), to_string(flux), st::to_string(time),
               k * k, st::admissible_courant(regular_layout_2d(k), setting, criterion).courant});
        }
  return out;
}

// The gist of a run's warning for a table cell: up to its first ';' or " (".
std::string short_note(const std::string& warning) {
  const std::size_t end = std::min(warning.find(';'), warning.find(" ("));
  return warning.substr(0, end);
}

const char* scheme_name(int s) {
  return s == 0 ? "Euler" : "RK2";
}
const char* criterion_name(int c) {
  return c == 0 ? "L2" : "monotone";
}

}  // namespace

std::vector<std::string> report_csv_files() {
  std::vector<std::string> files = {"runs.csv",
                                    "orders.csv",
                                    "best_per_budget.csv",
                                    "stability_map.csv",
                                    "courant_vs_particles.csv",
                                    "stiff_cases.csv",
                                    "plane_waves.csv",
                                    "plane_wave_orders.csv",
                                    "stability_map_2d.csv",
                                    "courant_vs_particles_2d.csv"};
  const std::vector<std::string> plastic = plasticity_csv_files();
  files.insert(files.end(), plastic.begin(), plastic.end());
  const std::vector<std::string> finite = finite_strain_csv_files();
  files.insert(files.end(), finite.begin(), finite.end());
  return files;
}

std::vector<std::string> report_png_files() {
  std::vector<std::string> files = {"error_vs_time_two_bar.png",
                                    "error_vs_time_smooth_pulse.png",
                                    "convergence_two_bar.png",
                                    "convergence_smooth_pulse.png",
                                    "stability_maps.png",
                                    "courant_vs_particles.png",
                                    "plate_before_reflection.png",
                                    "plate_after_reflection.png",
                                    "error_vs_time_plane_wave_p_30deg.png",
                                    "convergence_plane_wave_p_30deg.png",
                                    "stability_maps_2d.png",
                                    "courant_vs_particles_2d.png"};
  const std::vector<std::string> plastic = plasticity_png_files();
  files.insert(files.end(), plastic.begin(), plastic.end());
  const std::vector<std::string> finite = finite_strain_png_files();
  files.insert(files.end(), finite.begin(), finite.end());
  return files;
}

namespace {

// Best method per time budget (sections 1 and 6).
struct Best {
  std::string problem;
  double budget;
  const RunRow* row;
};

// The report in steps: each study runs into these members, then the CSV files, the plots and
// report.md are written from them (one function per part, in the report's order).
struct ReportBuilder {
  ReportBuilder(const ReportOptions& report_options, std::ostream& report_log)
      : options(report_options), log(report_log), dir(report_options.out) {}
  ReportBuilder(const ReportBuilder&) = delete;  // by_label points into methods
  ReportBuilder& operator=(const ReportBuilder&) = delete;

  const ReportOptions& options;
  std::ostream& log;
  const std::string& dir;
  ReportResult result;
  Environment env;
  std::vector<Method> methods, methods_2d;
  std::map<std::string, const Method*> by_label, by_label_2d;
  StabilityData stab;
  std::vector<double> maps[2][2];
  std::vector<StiffCase> stiff;
  Stability2D stab_2d;
  PlasticitySection plasticity;
  int plasticity_plots = 0;
  FiniteStrainSection finite_strain;
  int finite_strain_plots = 0;
  std::vector<Best> best;
  clock_type::time_point phase;
  double accuracy_seconds = 0, stability_seconds = 0, stiff_seconds = 0, plate_seconds = 0;
  double plane_wave_seconds = 0, stability_2d_seconds = 0, plot_seconds = 0;

  void run_accuracy();
  void run_stability();
  void run_stiff_and_plate();
  void run_plane_waves();
  void run_2d_stability_and_plasticity();
  void find_best();
  void write_csv();
  void plot();
  void markdown_header(std::ostream& md) const;
  void markdown_best(std::ostream& md, const std::vector<std::string>& problems) const;
  void markdown_accuracy(std::ostream& md) const;
  void markdown_stability_and_stiff(std::ostream& md) const;
  void markdown_plate_and_plane_waves(std::ostream& md) const;
  void markdown_2d_stability(std::ostream& md) const;
};

void ReportBuilder::run_accuracy() {
  // 1-2. Accuracy against time and cell size.
  methods = accuracy_methods();
  for (const Method& m : methods) by_label[m.spec.label] = &m;
  phase = clock_type::now();
  for (Problem p : {Problem::two_bar, Problem::smooth_pulse}) {
    for (const Method& m : methods) {
      for (int cells : grids(p, options.quick)) {
        // Two bars: energy is conserved; growth by 10% is a blow-up, not the scheme's error.
        RunRow r = run_scene(scene_for(p, cells, m.spec),
                             p == Problem::two_bar ? std::optional<double>(0.1) : std::nullopt);
        r.problem = to_string(p);
        r.label = m.spec.label;
        result.runs.push_back(r);
      }
      // Once a method blows up on a grid, finer grids at the same Courant number do too; they
      // still run (cost is bounded by the grid sequence) so the table shows them.
    }
    log << "  " << to_string(p) << ": " << methods.size() << " methods, done at "
        << fixed(seconds_since(phase), 1) << " s" << std::endl;
  }
  for (Problem p : {Problem::two_bar, Problem::smooth_pulse})
    for (const Method& m : methods)
      result.orders.push_back(fit_order(to_string(p), m.spec.label, result.runs));
  accuracy_seconds = seconds_since(phase);
}

void ReportBuilder::run_stability() {
  // 3. Stability maps and regular layouts.
  phase = clock_type::now();
  stab.map_size = options.quick ? 24 : 64;
  for (int s = 0; s < 2; ++s)
    for (int c = 0; c < 2; ++c) {
      const auto scheme = s == 0 ? st::TimeScheme::euler : st::TimeScheme::rk2;
      const auto criterion = c == 0 ? st::Criterion::l2 : st::Criterion::monotone;
      maps[s][c] =
          st::two_particle_courant_map(stab.map_size, {}, scheme, criterion, st::Model::elastic);
      for (int n = 1; n <= 8; ++n)
        stab.regular[s][c][n - 1] =
            st::admissible_courant(st::regular_layout(n), scheme, criterion).courant;
    }
  stability_seconds = seconds_since(phase);
  log << "  stability maps (" << stab.map_size << " x " << stab.map_size
      << "): " << fixed(stability_seconds, 1) << " s" << std::endl;
}

void ReportBuilder::run_stiff_and_plate() {
  // 4. Stiff and extreme cases with automatic time steps.
  phase = clock_type::now();
  stiff = stiff_cases(options.quick);
  for (const StiffCase& sc : stiff) {
    RunRow r = run_scene(sc.scene, 1e-6, 0.0);
    r.problem = "stiff";
    r.label = sc.name;
    result.stiff.push_back(r);
  }
  stiff_seconds = seconds_since(phase);
  log << "  stiff cases: " << fixed(stiff_seconds, 1) << " s" << std::endl;

  // 5. The 2D plate.
  phase = clock_type::now();
  for (const PlateRun& run : plate_runs) run_plate(run, dir);
  plate_seconds = seconds_since(phase);
  log << "  2D plate: " << fixed(plate_seconds, 1) << " s" << std::endl;
}

void ReportBuilder::run_plane_waves() {
  // 6. 2D plane waves: accuracy against time and cell size.
  phase = clock_type::now();
  methods_2d = plane_wave_methods(options.quick);
  for (const Method& m : methods_2d) {
    by_label_2d[m.spec.label] = &m;
    for (int cells : plane_wave_grids(options.quick)) {
      RunRow r = run_scene(plane_wave_scene(cells, m.spec), std::nullopt);
      r.problem = plane_wave_problem;
      r.label = m.spec.label;
      result.plane_waves.push_back(r);
    }
    result.plane_orders.push_back(fit_order(plane_wave_problem, m.spec.label, result.plane_waves));
  }
  plane_wave_seconds = seconds_since(phase);
  log << "  2D plane waves: " << methods_2d.size() << " methods, " << fixed(plane_wave_seconds, 1)
      << " s" << std::endl;
}

void ReportBuilder::run_2d_stability_and_plasticity() {
  // 7. 2D stability.
  phase = clock_type::now();
  stab_2d = stability_2d(options.quick);
  stability_2d_seconds = seconds_since(phase);
  log << "  2D stability: " << fixed(stability_2d_seconds, 1) << " s" << std::endl;

  // 8. Solids that yield (runs, and their plots when asked).
  plasticity = plasticity_section(dir, options.quick, options.plots, plasticity_plots, log);
  result.files.insert(result.files.end(), plasticity.files.begin(), plasticity.files.end());

  // 9. Finite strain.
  finite_strain =
      finite_strain_section(dir, options.quick, options.plots, finite_strain_plots, log);
  result.files.insert(result.files.end(), finite_strain.files.begin(), finite_strain.files.end());
}

void ReportBuilder::find_best() {
  // Best method per time budget: the smallest error among the stable runs within the budget.
  const std::pair<std::string, const std::vector<RunRow>*> studies[] = {
      {to_string(Problem::two_bar), &result.runs},
      {to_string(Problem::smooth_pulse), &result.runs},
      {plane_wave_problem, &result.plane_waves}};
  for (const auto& [problem, rows] : studies) {
    double lo = std::numeric_limits<double>::infinity(), hi = 0;
    for (const RunRow& r : *rows)
      if (r.problem == problem && r.stable) {
        lo = std::min(lo, r.wall_seconds);
        hi = std::max(hi, r.wall_seconds);
      }
    if (!(hi > 0)) continue;
    // Budgets at every power of ten (and 3x) between the fastest and the slowest run.
    for (double decade = std::pow(10.0, std::floor(std::log10(lo))); decade <= hi * 10;
         decade *= 10)
      for (double budget : {decade, 3 * decade}) {
        if (budget < lo || budget > 3 * hi) continue;
        const RunRow* pick = nullptr;
        for (const RunRow& r : *rows)
          if (r.problem == problem && r.stable && r.wall_seconds <= budget &&
              (!pick || r.l2_error < pick->l2_error))
            pick = &r;
        if (pick) best.push_back({problem, budget, pick});
      }
  }
}

void ReportBuilder::write_csv() {
  // CSV files. Runs and fitted orders have one layout for the 1D and the 2D studies.
  const auto write_runs = [&](const char* name, const std::vector<RunRow>& rows,
                              const std::map<std::string, const Method*>& methods_by_label) {
    write_file(dir, name, result.files, [&](std::ostream& out) {
      out << run_header;
      for (const RunRow& r : rows) write_run(out, r, *methods_by_label.at(r.label));
    });
  };
  const auto write_orders = [&](const char* name, const std::vector<OrderFit>& fits) {
    write_file(dir, name, result.files, [&](std::ostream& out) {
      out << "problem,label,order,intercept,points,note\n";
      for (const OrderFit& f : fits)
        out << f.problem << ',' << f.label << ',' << num(f.order) << ',' << num(f.intercept) << ','
            << f.points << ',' << f.note << '\n';
    });
  };
  write_runs("runs.csv", result.runs, by_label);
  write_orders("orders.csv", result.orders);
  write_file(dir, "best_per_budget.csv", result.files, [&](std::ostream& out) {
    out << "problem,budget_seconds,label,cells,wall_seconds,l2_error\n";
    for (const Best& b : best)
      out << b.problem << ',' << num(b.budget) << ',' << b.row->label << ',' << b.row->cells << ','
          << num(b.row->wall_seconds) << ',' << num(b.row->l2_error) << '\n';
  });
  write_file(dir, "stability_map.csv", result.files, [&](std::ostream& out) {
    out << "scheme,criterion,x1,x2,courant\n";
    const int n = stab.map_size;
    for (int s = 0; s < 2; ++s)
      for (int c = 0; c < 2; ++c)
        for (int i = 0; i < n; ++i)
          for (int j = 0; j < n; ++j)
            out << scheme_name(s) << ',' << criterion_name(c) << ',' << num((i + 0.5) / n) << ','
                << num((j + 0.5) / n) << ',' << num(maps[s][c][i * n + j]) << '\n';
  });
  write_file(dir, "courant_vs_particles.csv", result.files, [&](std::ostream& out) {
    out << "scheme,criterion,particles,courant\n";
    for (int s = 0; s < 2; ++s)
      for (int c = 0; c < 2; ++c)
        for (int n = 1; n <= 8; ++n)
          out << scheme_name(s) << ',' << criterion_name(c) << ',' << n << ','
              << num(stab.regular[s][c][n - 1]) << '\n';
  });
  write_file(dir, "stiff_cases.csv", result.files, [&](std::ostream& out) {
    out << "case,courant_used,dt_min,dt_max,steps,energy_drift,max_error,stable,failure,"
           "warning\n";
    for (std::size_t k = 0; k < stiff.size(); ++k) {
      const RunRow& r = result.stiff[k];
      out << csv_text(r.label) << ',' << num(r.dt_min * stiff[k].courant_reference) << ','
          << num(r.dt_min) << ',' << num(r.dt_max) << ',' << r.steps << ',' << num(r.energy_drift)
          << ',' << num(r.max_error) << ',' << (r.stable ? 1 : 0) << ',' << csv_text(r.failure)
          << ',' << csv_text(r.warning) << '\n';
    }
  });

  write_runs("plane_waves.csv", result.plane_waves, by_label_2d);
  write_orders("plane_wave_orders.csv", result.plane_orders);
  write_file(dir, "stability_map_2d.csv", result.files, [&](std::ostream& out) {
    out << "setting,x,y,courant\n";
    const int n = stab_2d.map_size;
    for (const auto& panel : stab_2d.panels)
      for (int j = 0; j < n; ++j)
        for (int i = 0; i < n; ++i)
          out << panel.name << ',' << num((i + 0.5) / n) << ',' << num((j + 0.5) / n) << ','
              << num(panel.courant[j * n + i]) << '\n';
  });
  write_file(dir, "courant_vs_particles_2d.csv", result.files, [&](std::ostream& out) {
    out << "model,criterion,flux,integrator,particles,courant\n";
    for (const auto& r : stab_2d.regular)
      out << r.model << ',' << r.criterion << ',' << r.flux << ',' << r.integrator << ','
          << r.particles << ',' << num(r.courant) << '\n';
  });
}

void ReportBuilder::plot() {
  // Plots.
  phase = clock_type::now();
  result.plot_status = options.plots ? run_python("plot.py", {dir}, log) : 0;
  if (options.plots)
    for (const auto& [k, when, name] :
         {std::tuple{0, "5e-4 s", "before"}, std::tuple{1, "1e-3 s", "after"}}) {
      std::vector<std::string> args = {dir, "--files"};
      for (const PlateRun& run : plate_runs)
        args.push_back(std::string("plate_") + run.tag + "/particles_00" + std::to_string(k) +
                       ".csv");
      args.push_back("--labels");
      for (const PlateRun& run : plate_runs) args.push_back(run.title);
      for (const std::string& a : std::vector<std::string>{
               "--cell", num(4.0 / 33), "0.12", "--field", "sigma_xx", "--title",
               std::string("plate impact, sigma_xx at ") + when + " (" + name +
                   " the reflection on the right edge)",
               "-o", dir + "/plate_" + name + "_reflection.png"})
        args.push_back(a);
      const int status = run_python("plot_fields_2d.py", args, log);
      if (result.plot_status == 0) result.plot_status = status;
    }
  if (result.plot_status == 0) result.plot_status = plasticity_plots;
  if (result.plot_status == 0) result.plot_status = finite_strain_plots;
  plot_seconds = seconds_since(phase);
  if (options.plots)
    for (const std::string& png : report_png_files()) result.files.push_back(dir + "/" + png);
  log << "  plots: " << fixed(plot_seconds, 1) << " s (status " << result.plot_status << ")"
      << std::endl;
}

void ReportBuilder::markdown_header(std::ostream& md) const {
  md << "# DGMPM report" << (options.quick ? " (quick mode)" : "") << "\n\n";
  md << "| | |\n| --- | --- |\n";
  md << "| dgmpm | " << version() << " |\n";
  md << "| commit | `" << env.commit << "` |\n";
  md << "| build type | " << env.build_type << " |\n";
  md << "| CPU | " << env.cpu << " |\n";
  md << "| cores | " << env.cores << " |\n";
  md << "| threads | " << omp_get_max_threads()
     << " (OpenMP: the 2D stability analysis, and steps on grids of 4096 cells or more) |\n";
  md << "| load at the start | " << env.load << " (1, 5, 15 min averages, /proc/loadavg) |\n";
  md << "| date | " << env.date << " |\n";
  md << "| report time | " << fixed(result.wall_seconds, 1) << " s (accuracy runs "
     << fixed(accuracy_seconds, 1) << " s, stability " << fixed(stability_seconds, 1)
     << " s, stiff cases " << fixed(stiff_seconds, 1) << " s, 2D plate " << fixed(plate_seconds, 1)
     << " s, 2D plane waves " << fixed(plane_wave_seconds, 1) << " s, 2D stability "
     << fixed(stability_2d_seconds, 1) << " s, solids that yield " << fixed(plasticity.seconds, 1)
     << " s, finite strain " << fixed(finite_strain.seconds, 1) << " s, plots "
     << fixed(plot_seconds, 1) << " s) |\n\n";
  if (result.plot_status != 0)
    md << "**The plotting script failed (status " << result.plot_status
       << "): the figures below are missing or stale.**\n\n";
}

void ReportBuilder::markdown_best(std::ostream& md,
                                  const std::vector<std::string>& problems) const {
  md << "Best method per time budget (smallest error among the stable runs that finish "
        "within the budget):\n\n| problem | budget (s) | method | cells | wall (s) | L2 error "
        "|\n| --- | --- | --- | --- | --- | --- |\n";
  for (const Best& b : best)
    if (std::find(problems.begin(), problems.end(), b.problem) != problems.end())
      md << "| " << b.problem << " | " << sci(b.budget, 0) << " | " << b.row->label << " | "
         << b.row->cells << " | " << sci(b.row->wall_seconds) << " | " << sci(b.row->l2_error)
         << " |\n";
}

void ReportBuilder::markdown_accuracy(std::ostream& md) const {
  md << "## 1. Error against run time\n\n"
        "Relative L2 error of the stress over the particles (volume weighted) at a fixed time, "
        "against the wall-clock time of the whole run (set-up, including the automatic time "
        "step's stability analysis, and the time loop; best of up to 5 repeats for short runs), "
        "one curve per method over a sequence of grids. Lower left is better: for a time "
        "budget, read the lowest curve left of it.\n\n"
        "* **two_bar**: the founding paper's impact of two steel bars (3 m each, +-v0, "
        "sigma = 4 GPa), compared at t = 2 m / c (fronts at 1 m from the ends); "
        "piecewise-constant exact solution.\n"
        "* **smooth_pulse**: a steel bar [0, 1] m at rest, free at x = 0, loaded at x = 1 by a "
        "sin^2 compression pulse of 100 MPa and 0.3 m (a time table of 2001 points), compared "
        "at t = 0.8 m / c, before the pulse reaches x = 0.\n\n"
        "Left: every method at the common Courant number "
     << common_courant << " (below the C* of every layout used; MPM with " << mpm_ppc
     << " particle per cell, since USL with 1 ppc is unstable above 1/sqrt(2)). Right: DGMPM "
        "at its automatic time step (C* of each cell's layout, L2, safety 1), with the MPM "
        "curves of the left panel, thin, for reference. Colour: method family (DGMPM Euler "
        "blue, RK2 green; MPM USL red, USF purple, MUSL orange, lighter for PIC); marker: "
        "particles per cell; dashed lines mean the automatic time step in every figure. Where "
        "C* = 1 (one particle per cell, and RK2) the automatic step is Courant 1, where DGMPM "
        "transports the waves exactly: those runs sit in the grey round-off band at the foot "
        "of the panel (errors below 1e-12). Unstable runs (exception, non-finite state, relative "
        "error above 1, or on the two bars energy growth above 10%) are left out and flagged "
        "in `runs.csv`.\n\n"
        "![](error_vs_time_two_bar.png)\n\n![](error_vs_time_smooth_pulse.png)\n\n";
  markdown_best(md, {to_string(Problem::two_bar), to_string(Problem::smooth_pulse)});
  int unstable = 0;
  for (const RunRow& r : result.runs) unstable += r.stable ? 0 : 1;
  md << "\n" << result.runs.size() << " runs, " << unstable << " unstable";
  if (unstable > 0) {
    md << ":";
    for (const RunRow& r : result.runs)
      if (!r.stable)
        md << " " << r.label << " (" << r.problem << ", " << r.cells
           << " cells: " << markdown_text(r.failure) << ");";
  }
  md << "\n\n";

  md << "## 2. Convergence\n\n"
        "Relative L2 stress error against cell size h; order = slope of the least-squares line "
        "through (log h, log error) (GSL `gsl_fit_linear`) over the stable grids whose error "
        "is above round-off ("
     << sci(roundoff_error, 0)
     << "). Discontinuous solutions (two_bar) limit every method to low orders; smooth_pulse "
        "shows the schemes' own order.\n\n"
        "![](convergence_two_bar.png)\n\n![](convergence_smooth_pulse.png)\n\n"
        "| method | two_bar order | smooth_pulse order |\n| --- | --- | --- |\n";
  for (const Method& m : methods) {
    md << "| " << m.spec.label;
    for (Problem p : {Problem::two_bar, Problem::smooth_pulse})
      for (const OrderFit& f : result.orders)
        if (f.problem == to_string(p) && f.label == m.spec.label)
          md << " | "
             << (f.note.empty() ? fixed(f.order, 2) + " (" + std::to_string(f.points) + " grids)"
                                : "n/a: " + f.note);
    md << " |\n";
  }
}

void ReportBuilder::markdown_stability_and_stiff(std::ostream& md) const {
  md << "\n## 3. Stability\n\n"
        "Admissible Courant number C* (docs/method.md, section Stability: the largest C such "
        "that every C' in (0, C] "
        "passes) of the elastic bar, for two equal particles at local positions (x1, x2) of "
        "every cell ("
     << stab.map_size << " x " << stab.map_size
     << " layouts), and for N regular particles per cell, (k + 1/2) / N.\n\n"
        "![](stability_maps.png)\n\n![](courant_vs_particles.png)\n\n"
        "| N | Euler L2 | Euler monotone | RK2 L2 | RK2 monotone |\n| --- | --- | --- | --- | "
        "--- |\n";
  for (int n = 1; n <= 8; ++n)
    md << "| " << n << " | " << fixed(stab.regular[0][0][n - 1], 4) << " | "
       << fixed(stab.regular[0][1][n - 1], 4) << " | " << fixed(stab.regular[1][0][n - 1], 4)
       << " | " << fixed(stab.regular[1][1][n - 1], 4) << " |\n";

  md << "\n## 4. Stiff and extreme cases (automatic time step)\n\n"
        "Two steel bars (3 m each) impacting at +-v0 in a grid with a 0.5 m margin, "
     << (options.quick ? 10 : 25)
     << " cells per metre, free ends, run to t = 12 m / c (after the bars separate). Energy "
        "is conserved exactly, so growth above 1e-6 marks the run unstable; DGMPM dissipates "
        "(negative drift). C used = c dt / h with the smallest dt. Max error: relative max "
        "norm of the stress against the exact solution (n/a for the bi-material bar, which "
        "has none here). The last row runs a fixed Courant number above the layout's C* for "
        "contrast. Half-full end cells take the small-cell rule (C* times the cell's fill). "
        "Rows marked \"paper's formulation\" use the founding paper's scheme "
        "(scene key `formulation`: `paper`) instead of the consistent one: a part-full "
        "or over-full cell then does not preserve constant states, so the half-full ends "
        "radiate waves (with RK2 at safety 1 their start-up transient raises the energy) and "
        "moving particles piling up into a cell create new extrema whatever the time step "
        "(the note names the first such cell). Notes: the run's first warning.\n\n"
        "| case | C used | dt min (s) | dt max (s) | steps | energy drift | max error | stable "
        "| notes |\n| --- | --- | --- | --- | --- | --- | --- | --- | --- |\n";
  for (std::size_t k = 0; k < stiff.size(); ++k) {
    const RunRow& r = result.stiff[k];
    md << "| " << r.label << " | " << fixed(r.dt_min * stiff[k].courant_reference, 4) << " | "
       << sci(r.dt_min) << " | " << sci(r.dt_max) << " | " << r.steps << " | "
       << sci(r.energy_drift) << " | " << sci(r.max_error) << " | "
       << (r.stable ? "yes" : "no: " + markdown_text(r.failure)) << " | "
       << markdown_text(short_note(r.warning)) << " |\n";
  }
}

void ReportBuilder::markdown_plate_and_plane_waves(std::ostream& md) const {
  md << "\n## 5. The 2D plate\n\n"
        "The founding paper's plate (4 m x 3 m steel, -2e8 Pa on the lower metre of the left "
        "edge from t = 0, other edges free, 33 x 25 particles): sigma_xx before (5e-4 s) and "
        "after (1e-3 s) the P wave (c_p = 5875 m/s) reflects on the right edge at 6.8e-4 s. "
        "Each particle is drawn as a cell-sized square.\n\n";
  md << "DGMPM DCU with RK2 and CTU with Euler (both at Courant 1, where one particle per "
        "cell is exact for waves along the axes) and MPM USF (FLIP, Courant 0.5) side by "
        "side, on one colour scale. DGMPM keeps the fronts sharp (one or two cells) and the "
        "fields smooth behind them; MPM shows cell-to-cell noise of tens of MPa behind the "
        "fronts. After the reflection, tension (yellow) appears along the top edge.\n\n"
        "![sigma_xx before the reflection](plate_before_reflection.png)\n\n"
        "![sigma_xx after the reflection](plate_after_reflection.png)\n\n";

  md << "## 6. 2D plane waves\n\n"
        "The P plane wave travelling at 30 degrees to the x axis (`scenes/"
     << plane_wave_problem
     << ".json`: a sine wave of one wavelength on a doubly periodic grid, steel, nu = 0.3), "
        "run for one period and compared with its exact translation: relative L2 error of "
        "the stress over the particles. Cells are close to square (N x round(1.732 N)), N = ";
  {
    const auto g = plane_wave_grids(options.quick);
    for (std::size_t k = 0; k < g.size(); ++k) md << (k ? ", " : "") << g[k];
  }
  md << ". Left panel: every method at Courant " << common_courant
     << "; right: DGMPM at its automatic time step (dashed) with MPM for reference. Colours: "
        "DCU Euler blue, DCU RK2 green, CTU Euler olive, CTU RK2 brown; MPM USL red, USF "
        "purple, MUSL orange; marker: particles per cell. The wave is oblique to the grid, "
        "so no method is exact: this is the study of accuracy for a budget in 2D. On the "
        "coarse grids DGMPM's wall time is mostly set-up: the von Neumann analysis of the "
        "cell layout (for the automatic step, and to check a fixed Courant number), about "
        "0.1 s for one particle per cell (`dgmpm bench --what courant-2d`). On the finest "
        "grids the time loop takes most of the run; every method steps on the report's "
        "threads there (grids of 4096 cells or more), DGMPM and MPM with their fused, "
        "threaded sweeps.\n\n"
        "![](error_vs_time_plane_wave_p_30deg.png)\n\n"
        "![](convergence_plane_wave_p_30deg.png)\n\n"
        "| method | order | error on the finest grid | wall (s) |\n| --- | --- | --- | --- |\n";
  for (const Method& m : methods_2d) {
    const RunRow* finest = nullptr;
    for (const RunRow& r : result.plane_waves)
      if (r.label == m.spec.label && (!finest || r.cells > finest->cells)) finest = &r;
    md << "| " << m.spec.label << " | ";
    for (const OrderFit& f : result.plane_orders)
      if (f.label == m.spec.label) md << (f.note.empty() ? fixed(f.order, 2) : "n/a: " + f.note);
    md << " | " << (finest && finest->stable ? sci(finest->l2_error) : std::string("unstable"))
       << " | " << (finest ? sci(finest->wall_seconds) : std::string("")) << " |\n";
  }
  md << "\n";
  markdown_best(md, {plane_wave_problem});
}

void ReportBuilder::markdown_2d_stability(std::ostream& md) const {
  md << "\n## 7. 2D stability\n\n"
        "Admissible Courant number C* of plane strain (nu = 0.3, C = c_p dt / h) for one "
        "particle per cell as a function of where it sits in the cell ("
     << stab_2d.map_size << " x " << stab_2d.map_size
     << " positions), for RK2 with DCU and Euler with CTU: the two pairs exact at Courant 1 "
        "for a centred particle. Under RK2 an off-centre particle lowers C* (the second stage "
        "sees unequal nodal masses: a weak long-wave instability, docs/method.md, Stability); "
        "under Euler CTU C* does not depend on the position. Computed range:";
  for (const auto& panel : stab_2d.panels) {
    const auto [lo, hi] = std::minmax_element(panel.courant.begin(), panel.courant.end());
    md << " " << panel.name << " from " << sci(*lo, 3) << " to " << fixed(*hi, 4) << ";";
  }
  md << " the colour scale is logarithmic when C* spans more than a decade.\n\n"
        "![](stability_maps_2d.png)\n\n"
        "C* of N regular particles per cell (positions ((i + 1/2) / n, (j + 1/2) / n), N = "
        "n^2) for every flux x integrator, for scalar advection u_t + u_x + u_y = 0 (L2 and "
        "monotone criteria) and plane strain (L2; the monotone criterion needs scalar waves):"
        "\n\n![](courant_vs_particles_2d.png)\n\n"
        "| model | criterion | flux | integrator |";
  std::vector<int> counts;
  for (const auto& r : stab_2d.regular)
    if (std::find(counts.begin(), counts.end(), r.particles) == counts.end())
      counts.push_back(r.particles);
  for (int n : counts) md << " N = " << n << " |";
  md << "\n| --- | --- | --- | --- |";
  for (std::size_t k = 0; k < counts.size(); ++k) md << " --- |";
  for (std::size_t k = 0; k < stab_2d.regular.size(); k += counts.size()) {
    const auto& r = stab_2d.regular[k];
    md << "\n| " << r.model << " | " << r.criterion << " | " << r.flux << " | " << r.integrator
       << " |";
    for (std::size_t c = 0; c < counts.size(); ++c)
      md << " "
         << (stab_2d.regular[k + c].courant < 0.01 ? sci(stab_2d.regular[k + c].courant, 3)
                                                   : fixed(stab_2d.regular[k + c].courant, 4))
         << " |";
  }
  md << "\n\nRaw data: `runs.csv`, `orders.csv`, `best_per_budget.csv`, `stability_map.csv`, "
        "`courant_vs_particles.csv`, `stiff_cases.csv`, `plane_waves.csv`, "
        "`plane_wave_orders.csv`, `stability_map_2d.csv`, `courant_vs_particles_2d.csv`; the "
        "plate's particles in `plate_*/`.\n\n";
  md << plasticity.markdown;
  md << finite_strain.markdown;
}

}  // namespace

ReportResult write_report(const ReportOptions& options, std::ostream& log) {
  const auto start = clock_type::now();
  ReportBuilder report(options, log);
  output::create_directories(options.out);
  report.env = environment();
  log << "dgmpm report (" << (options.quick ? "quick" : "full") << ") into " << options.out
      << std::endl;
  report.run_accuracy();
  report.run_stability();
  report.run_stiff_and_plate();
  report.run_plane_waves();
  report.run_2d_stability_and_plasticity();
  report.find_best();
  report.write_csv();
  report.plot();
  ReportResult& result = report.result;
  result.wall_seconds = seconds_since(start);
  write_file(options.out, "report.md", result.files, [&](std::ostream& md) {
    report.markdown_header(md);
    report.markdown_accuracy(md);
    report.markdown_stability_and_stiff(md);
    report.markdown_plate_and_plane_waves(md);
    report.markdown_2d_stability(md);
  });
  log << "wrote " << options.out << "/report.md in " << fixed(seconds_since(start), 1) << " s"
      << std::endl;
  return result;
}

}  // namespace dgmpm::report
