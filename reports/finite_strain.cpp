#include "reports/finite_strain.hpp"

#include "reports/report_io.hpp"
#include "solver/installation.hpp"
#include "solver/scene.hpp"
#include "solver/simulation.hpp"
#include "stability/gsl_guard.hpp"

#include <gsl/gsl_roots.h>

#include <nlohmann/json.hpp>

#include <algorithm>
#include <cmath>
#include <fstream>
#include <functional>
#include <limits>
#include <ostream>
#include <sstream>

namespace dgmpm::report {

namespace {

// Steel (the thesis's), uniaxial strain, a 6 m half-space (no wave reaches its far end).
constexpr double kYoung = 2e11, kPoisson = 0.3, kDensity = 7800, kLength = 6.0;
constexpr double kNan = std::numeric_limits<double>::quiet_NaN();
using SVK = FiniteStrainBar<SaintVenantKirchhoff>;
using NH = FiniteStrainBar<NeoHookean>;

struct Case {
  std::string name, title;
  bool svk;
  double load;   // nominal traction at X = 0 (Pa), or 0
  double speed;  // the halves' speed (impact), or 0
  double end;
};
const std::vector<Case>& cases() {
  static const std::vector<Case> c = {
      {"svk_2gpa", "SVK, 2 GPa tension", true, 2e9, 0, 6e-4},
      {"svk_20gpa", "SVK, 20 GPa tension", true, 2e10, 0, 6e-4},
      {"svk_fan", "SVK, 20 GPa compression", true, -2e10, 0, 6e-4},
      {"nh_impact", "neo-Hookean, +-100 m/s", false, 0, 100, 4e-4},
  };
  return c;
}

struct Method {
  std::string label, method;
  double courant;  // 0: "auto"
};
const std::vector<Method>& methods() {
  static const std::vector<Method> m = {{"DGMPM auto", "dgmpm", 0.0},
                                        {"DGMPM C = 1", "dgmpm", 1.0},
                                        {"MPM USL C = 0.5", "mpm-usl", 0.5},
                                        {"MPM MUSL C = 0.5", "mpm-musl", 0.5}};
  return m;
}

nlohmann::json scene_of(const Case& c, const Method& m, int cells) {
  const nlohmann::json steel = {{"model", c.svk ? "saint_venant_kirchhoff" : "neo_hookean"},
                                {"young", kYoung},
                                {"poisson", kPoisson},
                                {"density", kDensity}};
  const auto body = [&](double from, double to, double v) {
    return nlohmann::json{{"material", "steel"},
                          {"box", {{"min", {from}}, {"max", {to}}}},
                          {"particles_per_cell", 1},
                          {"velocity", {v}}};
  };
  nlohmann::json doc = {
      {"dimension", 1},
      {"method", m.method},
      {"grid", {{"origin", {0.0}}, {"cell_size", {kLength / cells}}, {"cells", {cells}}}},
      {"materials", {{"steel", steel}}},
      {"boundaries", {{"xmin", {{"type", "free"}}}, {"xmax", {{"type", "free"}}}}},
      {"time", {{"end", c.end}}}};
  if (m.courant > 0)
    doc["time"]["courant"] = m.courant;
  else
    doc["time"]["courant"] = "auto";
  if (c.speed > 0) {
    doc["bodies"] = {body(0, kLength / 2, c.speed), body(kLength / 2, kLength, -c.speed)};
  } else {
    doc["bodies"] = {body(0, kLength, 0.0)};
    doc["boundaries"]["xmin"] = {{"type", "traction"}, {"value", c.load}};
  }
  return doc;
}

// The root of g on [a, b] (g(a), g(b) of opposite signs) by GSL's Brent solver, to 1e-15
// relative.
double root(const std::function<double(double)>& g, double a, double b) {
  const stability::GslErrorsAsCodes guard;
  gsl_function f{[](double x, void* p) { return (*static_cast<decltype(&g)>(p))(x); },
                 const_cast<void*>(static_cast<const void*>(&g))};
  gsl_root_fsolver* solver = gsl_root_fsolver_alloc(gsl_root_fsolver_brent);
  double x = 0.5 * (a + b);
  if (gsl_root_fsolver_set(solver, &f, a, b) == GSL_SUCCESS)
    for (int k = 0; k < 200; ++k) {
      if (gsl_root_fsolver_iterate(solver) != GSL_SUCCESS) break;
      x = gsl_root_fsolver_root(solver);
      const double lo = gsl_root_fsolver_x_lower(solver), hi = gsl_root_fsolver_x_upper(solver);
      if (gsl_root_test_interval(lo, hi, 0.0, 1e-15) == GSL_SUCCESS) break;
    }
  gsl_root_fsolver_free(solver);
  return x;
}

// The exact F(X, t): a shock (tension, impact) at speed s behind which F = f, or (compression)
// a fan whose F(xi) solves rho0 xi^2 = dP/dF between its head and tail.
template <class P>
struct Exact {
  typename P::Material m{kYoung, kPoisson, kDensity};
  double f = 1, s = 0, p = 0, head = 0, tail = 0;
  bool fan = false, impact = false;
  explicit Exact(const Case& c) {
    if (c.speed > 0) {  // v* = 0: F* = 1 - v0 / s with P(F*) = -rho0 v0 s
      impact = true;
      s = root(
          [&](double x) { return P::nominal_stress(1 - c.speed / x, m) + kDensity * c.speed * x; },
          1000, 20000);
      f = 1 - c.speed / s;
    } else {
      f = root([&](double x) { return P::nominal_stress(x, m) - c.load; }, c.load > 0 ? 1.0 : 0.6,
               c.load > 0 ? 2.0 : 1.0);
      fan = c.load < 0;
      if (fan) {
        head = P::wave_speed(1.0, m);
        tail = P::wave_speed(f, m);
      } else {
        s = std::sqrt(c.load / (kDensity * (f - 1)));
      }
    }
    p = P::nominal_stress(f, m);
  }
  double at(double x, double t) const {
    if (impact) return std::abs(x - kLength / 2) < s * t ? f : 1.0;
    if (!fan) return x < s * t ? f : 1.0;
    const double xi = x / t;
    if (xi >= head) return 1.0;
    if (xi <= tail) return f;
    return root([&](double g) { return P::tangent(g, m) - kDensity * xi * xi; }, f, 1.0);
  }
};

struct Row {
  std::string case_name, label;
  int cells = 0;
  long steps = 0;
  double overshoot = kNan;      // P at the front beyond the exact plateau's, relative
  double plateau_error = kNan;  // mean P over the plateau against the exact, relative
  double l1_error = kNan;       // of F over the jump (m)
  double courant_start = 0, courant_after = 0;
  double energy_excess = kNan;  // largest (E - E0 - W) / (E0 + W) over the steps (DGMPM)
};

struct Profile {
  std::vector<double> x, f, p;
};

template <class P>
Row run(const Case& c, const Method& m, int cells, Profile* profile) {
  const Exact<P> exact(c);
  Simulation<P> sim(scene::parse_scene(scene_of(c, m, cells), c.name));
  const auto& materials = sim.problem().materials;
  const auto fastest = [&] {
    double speed = 0;
    const auto& ps = sim.particles();
    for (int i = 0; i < ps.size(); ++i)
      speed = std::max(speed, P::state_wave_speed(ps.state.col(i), materials[ps.material[i]]));
    return speed;
  };
  const double h = kLength / cells, e0 = sim.energy();
  const bool dgmpm = m.method == "dgmpm";
  Row r{c.name, m.label, cells};
  if (dgmpm) r.energy_excess = -std::numeric_limits<double>::infinity();
  while (sim.time() < c.end) {
    const double c0 = fastest(), t0 = sim.time();
    sim.advance_to(std::min(c.end, t0 + sim.stable_time_step()));
    const double dt = sim.time() - t0;
    r.courant_start = std::max(r.courant_start, dt * c0 / h);
    r.courant_after = std::max(r.courant_after, dt * fastest() / h);
    if (dgmpm) {
      const double reference = e0 + sim.boundary_work();
      r.energy_excess = std::max(r.energy_excess, (sim.energy() - reference) / reference);
    }
    ++r.steps;
  }
  const auto& ps = sim.particles();
  double l1 = 0, p_sum = 0, p_extreme = 0;
  int plateau = 0;
  for (int i = 0; i < ps.size(); ++i) {
    const double x = ps.position(0, i), f = ps.state(0, i) * kDensity;
    const double p = P::nominal_stress(f, materials[ps.material[i]]);
    l1 += std::abs(f - exact.at(x, sim.time())) * h;
    // The plateau, half a metre clear of the front (and of the loaded end).
    const double reach = exact.s * sim.time();
    const bool in =
        exact.impact ? std::abs(x - kLength / 2) < reach - 0.5 : x > 0.5 && x < reach - 0.5;
    if (in) p_sum += p, ++plateau;
    p_extreme = exact.p > 0 ? std::max(p_extreme, p) : std::min(p_extreme, p);
    if (profile) profile->x.push_back(x), profile->f.push_back(f), profile->p.push_back(p);
  }
  r.l1_error = l1 / std::abs(exact.f - 1);
  if (!exact.fan) {
    r.overshoot = p_extreme / exact.p - 1;
    r.plateau_error = p_sum / plateau / exact.p - 1;
  }
  return r;
}

Row run_case(const Case& c, const Method& m, int cells, Profile* profile) {
  return c.svk ? run<SVK>(c, m, cells, profile) : run<NH>(c, m, cells, profile);
}

// A relative number in percent, signed, with more digits below 0.1%.
std::string percent(double x) {
  if (std::isnan(x)) return "n/a";
  std::string s = x >= 0 ? "+" : "";
  s += fixed(100 * x, x != 0 && std::abs(x) < 1e-3 ? 4 : 2);
  s += '%';
  return s;
}

// The pressed plate (scenes/plate_finite_strain.json, neo-Hookean, plane strain) by DGMPM as
// shipped (DCU), with CTU, and by MPM USL, particle files at the end under
// dir/plate_finite_strain_<tag>.
struct PlateRun {
  const char* tag;
  const char* title;
};
const PlateRun plate_runs[] = {{"dgmpm", "DGMPM DCU Euler, auto"},
                               {"dgmpm_ctu", "DGMPM CTU Euler, auto"},
                               {"mpm_usl", "MPM USL (FLIP), Courant 0.5"}};
struct PlateResult {
  long steps = 0;
  double seconds = 0, displacement = 0, least_j = 1, least_sigma = 0, energy = 0, work = kNan;
};

PlateResult run_plate(const PlateRun& run, const std::string& dir) {
  using Plane = FiniteStrainPlane<NeoHookean>;
  nlohmann::json doc;
  std::ifstream(data_file("scenes/plate_finite_strain.json")) >> doc;
  const std::string tag = run.tag;
  if (tag == "dgmpm_ctu") doc["flux"] = "ctu";
  if (tag == "mpm_usl") {
    doc["method"] = "mpm-usl";
    doc["time"]["courant"] = 0.5;
  }
  const double end = doc["time"]["end"].get<double>();
  doc["output"] = {{"directory", dir + "/plate_finite_strain_" + run.tag},
                   {"times", {end}},
                   {"formats", {"csv"}}};
  Simulation<Plane> sim(scene::parse_scene(doc, std::string("pressed plate ") + run.tag));
  const RunSummary summary = sim.run();
  PlateResult r{summary.steps, summary.stepping_seconds};
  r.energy = summary.energy_final;  // from rest: the initial energy is 0
  // MPM's work of the loads is an estimate for its blow-up check (solver/mpm.hpp): not shown.
  if (tag != "mpm_usl") r.work = summary.boundary_work;
  const auto& ps = sim.particles();
  for (int i = 0; i < ps.size(); ++i) {
    const auto& m = sim.problem().materials[ps.material[i]];
    const Plane::State s = Plane::physical(ps.state.col(i), m);
    r.displacement = std::max(r.displacement, Plane::displacement_of(ps.internal.col(i)).norm());
    r.least_j = std::min(r.least_j, Plane::gradient(s).determinant());
    r.least_sigma =
        std::min(r.least_sigma, Plane::cauchy_stress_tensor(s, ps.internal.col(i), m)(0, 0));
  }
  return r;
}

}  // namespace

std::vector<std::string> finite_strain_csv_files() {
  return {"finite_strain_runs.csv", "finite_strain_profiles.csv", "finite_strain_fan.csv"};
}

std::vector<std::string> finite_strain_png_files() {
  return {"finite_strain_profiles.png", "finite_strain_plate.png"};
}

FiniteStrainSection finite_strain_section(const std::string& dir, bool quick, bool plots,
                                          int& plot_status, std::ostream& log) {
  const auto start = clock_type::now();
  FiniteStrainSection out;
  constexpr int kCells = 300;
  std::vector<Row> rows;
  write_file(dir, "finite_strain_profiles.csv", out.files, [&](std::ostream& csv) {
    csv << "case,label,x,F,nominal_stress\n";
    for (const Case& c : cases()) {
      for (const Method& m : methods()) {
        Profile profile;
        rows.push_back(run_case(c, m, kCells, &profile));
        for (std::size_t i = 0; i < profile.x.size(); ++i)
          csv << c.name << ',' << m.label << ',' << num(profile.x[i]) << ',' << num(profile.f[i])
              << ',' << num(profile.p[i]) << '\n';
      }
      for (int k = 0; k <= 3000; ++k) {
        const double x = kLength * k / 3000;
        const auto exact_f = [&](auto e) { return e.at(x, c.end); };
        const double f = c.svk ? exact_f(Exact<SVK>(c)) : exact_f(Exact<NH>(c));
        const double p = c.svk ? SVK::nominal_stress(f, SVK::Material(kYoung, kPoisson, kDensity))
                               : NH::nominal_stress(f, NH::Material(kYoung, kPoisson, kDensity));
        csv << c.name << ",exact," << num(x) << ',' << num(f) << ',' << num(p) << '\n';
      }
    }
  });
  write_file(dir, "finite_strain_runs.csv", out.files, [&](std::ostream& csv) {
    csv << "case,label,cells,steps,overshoot,plateau_error,l1_error_f,courant_start_max,"
           "courant_after_max,energy_excess_max\n";
    for (const Row& r : rows)
      csv << r.case_name << ',' << r.label << ',' << r.cells << ',' << r.steps << ','
          << num(r.overshoot) << ',' << num(r.plateau_error) << ',' << num(r.l1_error) << ','
          << num(r.courant_start) << ',' << num(r.courant_after) << ',' << num(r.energy_excess)
          << '\n';
  });
  log << "  finite strain runs: " << fixed(seconds_since(start), 1) << " s" << std::endl;

  // The fan's L1 error of F against the cell count.
  const std::vector<int> grids =
      quick ? std::vector<int>{300, 1200} : std::vector<int>{300, 1200, 4800};
  std::vector<Row> fan;
  for (const Method& m : {methods()[0], methods()[2]})
    for (int cells : grids) fan.push_back(run_case(cases()[2], m, cells, nullptr));
  write_file(dir, "finite_strain_fan.csv", out.files, [&](std::ostream& csv) {
    csv << "label,cells,l1_error_f\n";
    for (const Row& r : fan) csv << r.label << ',' << r.cells << ',' << num(r.l1_error) << '\n';
  });
  log << "  finite strain fan: " << fixed(seconds_since(start), 1) << " s" << std::endl;
  std::vector<PlateResult> plates;
  for (const PlateRun& run : plate_runs) {
    plates.push_back(run_plate(run, dir));
    out.files.push_back(dir + "/plate_finite_strain_" + run.tag + "/particles_000.csv");
  }
  out.seconds = seconds_since(start);
  log << "  finite strain plate: " << fixed(out.seconds, 1) << " s" << std::endl;
  if (plots) {
    int status = run_python("plot_finite_strain.py", {dir}, log);
    std::vector<std::string> args = {dir, "--files"};
    std::vector<std::string> labels = {"--labels"};
    for (const PlateRun& run : plate_runs) {
      args.push_back(std::string("plate_finite_strain_") + run.tag + "/particles_000.csv");
      labels.push_back(run.title);
    }
    args.insert(args.end(), labels.begin(), labels.end());
    for (const char* a :
         {"--cell", "0.005", "0.005", "--field", "sigma_xx", "--scale", "1e-9", "--unit", "GPa",
          "--deformed", "--title",
          "neo-Hookean plate pressed by 30 GPa, 6e-5 s: Cauchy sigma_xx on the deformed "
          "body (reference outline dashed)",
          "-o"})
      args.push_back(a);
    args.push_back(dir + "/finite_strain_plate.png");
    const int plate_status = run_python("plot_fields_2d.py", args, log);
    if (status == 0) status = plate_status;
    if (plot_status == 0) plot_status = status;
  }

  const auto find = [&](const std::string& c, const std::string& label) {
    for (const Row& r : rows)
      if (r.case_name == c && r.label == label) return r;
    return Row{};
  };
  std::ostringstream md;
  md << "## 9. Finite strain\n\n"
        "**Hyperelastic half-spaces** (Renaud, Heuzé, Stainier 2018; thesis ch. 2-4): steel (E = "
        "2e11 Pa, nu = 0.3, rho0 = 7800 kg/m^3) in uniaxial strain, total Lagrangian, one "
        "particle per cell, "
     << kCells
     << " cells over 6 m. Saint Venant-Kirchhoff pulled at its end by 2 and 20 GPa (shocks) "
        "and pushed by 20 GPa (a fan); neo-Hookean halves meeting at +-100 m/s. DGMPM Euler "
        "with the automatic step (0.9 times the admissible Courant number, docs/method.md) and at "
        "Courant 1; the MPM baseline (USL and MUSL, FLIP, the same total Lagrangian form) at 0.5 "
        "(USL at one "
        "particle per cell blows up at 0.8 on the 2 GPa shock). "
        "Exact values from the jump and fan relations of the laws.\n\n"
        "| case | method | steps | overshoot at the front | plateau P error | L1 error of F "
        "/ jump (m) | Courant, speeds at the step's start / after | energy excess |\n"
        "| --- | --- | --- | --- | --- | --- | --- | --- |\n";
  for (const Row& r : rows) {
    std::string title;
    for (const Case& c : cases())
      if (c.name == r.case_name) title = c.title;
    md << "| " << title << " | " << r.label << " | " << r.steps << " | " << percent(r.overshoot)
       << " | " << (std::isnan(r.plateau_error) ? "n/a" : sci(r.plateau_error, 1)) << " | "
       << sci(r.l1_error, 2) << " | " << fixed(r.courant_start, 3) << " / "
       << fixed(r.courant_after, 3) << " | "
       << (std::isnan(r.energy_excess) ? "n/a" : sci(r.energy_excess, 1)) << " |\n";
  }
  md << "\n**Overshoots at the shock, beside the thesis's** (nominal stress at the front over "
        "the exact plateau, SVK; the thesis: DGMPM +0.45% at 2 GPa and +2.5% at 20 GPa, MPM +21% "
        "and +27%):\n\n"
        "| load | DGMPM auto | DGMPM C = 1 | MPM USL C = 0.5 | MPM MUSL C = 0.5 | thesis DGMPM | "
        "thesis MPM |\n| --- | --- | --- | --- | --- | --- | --- |\n";
  for (const auto& [name, load, thesis_dg, thesis_mpm] :
       {std::tuple{"svk_2gpa", "2 GPa", "+0.45%", "+21%"},
        std::tuple{"svk_20gpa", "20 GPa", "+2.5%", "+27%"}}) {
    md << "| " << load;
    for (const Method& m : methods()) md << " | " << percent(find(name, m.label).overshoot);
    md << " | " << thesis_dg << " | " << thesis_mpm << " |\n";
  }
  md << "\nThe energy excess is the largest `(E - E0 - W) / (E0 + W)` over the steps (kinetic + "
        "strain energy against the initial energy plus the loads' work): positive at Courant 1 "
        "where a step chosen with the speeds at its start meets a state behind the front that "
        "moves faster (the Courant number measured with the speeds after the step reaches "
     << fixed(find("svk_20gpa", "DGMPM C = 1").courant_after, 3)
     << " at 20 GPa), negative with the automatic step. MPM's balance is not tracked (n/a).\n\n"
        "**The fan's convergence** (L1 error of F over the jump, m):\n\n"
        "| cells |";
  for (int cells : grids) md << ' ' << cells << " |";
  md << " order |\n| --- |";
  for (std::size_t k = 0; k <= grids.size(); ++k) md << " --- |";
  md << '\n';
  for (const std::string& label : {methods()[0].label, methods()[2].label}) {
    md << "| " << label << " |";
    std::vector<double> e;
    for (const Row& r : fan)
      if (r.label == label) e.push_back(r.l1_error), md << ' ' << sci(r.l1_error, 2) << " |";
    md << ' ' << fixed(std::log(e[e.size() - 2] / e.back()) / std::log(4.0), 2) << " |\n";
  }
  md << "\n![finite-strain profiles](finite_strain_profiles.png)\n\n"
        "**A pressed plate in plane strain** (`scenes/plate_finite_strain.json`): a neo-Hookean "
        "steel plate 0.4 m x 0.2 m at rest, 80 x 40 cells, one particle per cell, on a roller "
        "along y = 0; the first 0.05 m of its left side pressed by a nominal pressure of 30 GPa (a "
        "traction boundary), 6e-5 s. DGMPM (DCU and CTU, Euler, the automatic step from the "
        "particles' largest speed over directions) and the MPM baseline (total Lagrangian) on the "
        "same scene:\n\n"
        "| method | steps | stepping (s) | largest displacement (m) | least J | least sigma_xx "
        "(GPa) | final energy (J/m) | work of the load (J/m) |\n"
        "| --- | --- | --- | --- | --- | --- | --- | --- |\n";
  for (std::size_t k = 0; k < plates.size(); ++k) {
    const PlateResult& p = plates[k];
    md << "| " << plate_runs[k].title << " | " << p.steps << " | " << fixed(p.seconds, 2) << " | "
       << fixed(p.displacement, 4) << " | " << fixed(p.least_j, 3) << " | "
       << fixed(p.least_sigma * 1e-9, 1) << " | " << sci(p.energy, 3) << " | "
       << (std::isnan(p.work) ? "n/a" : sci(p.work, 3)) << " |\n";
  }
  md << "\nThe load's end at y = 0.05 m is a singular point of the solution (the nominal traction "
        "jumps from 30 GPa to zero there): the cells next to it shear by order one within the "
        "first 1e-5 s, the largest displacement and velocity sit near it and grow as the grid is "
        "refined, and the methods differ most there. The largest displacement above measures that "
        "corner; it is not a converged quantity.\n";
  md << "\n![pressed plate](finite_strain_plate.png)\n\n"
        "Raw data: `finite_strain_runs.csv`, `finite_strain_profiles.csv`, "
        "`finite_strain_fan.csv`, `plate_finite_strain_*/`.\n\n";
  out.markdown = md.str();
  return out;
}

}  // namespace dgmpm::report
