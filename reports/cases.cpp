#include "reports/cases.hpp"

#include "solver/scene.hpp"
#include "solver/simulation.hpp"

#include <chrono>
#include <cmath>
#include <exception>
#include <limits>
#include <memory>
#include <numbers>

namespace dgmpm::report {

namespace {

constexpr double young = 2e11, density = 7800;
const double wave_speed = std::sqrt(young / density);

nlohmann::json steel() {
  return {
      {"steel",
       {{"model", "linear_elastic"}, {"young", young}, {"poisson", 0.3}, {"density", density}}}};
}

nlohmann::json body(double lo, double hi, double v, int ppc) {
  return {{"material", "steel"},
          {"box", {{"min", {lo}}, {"max", {hi}}}},
          {"particles_per_cell", ppc},
          {"velocity", {v}},
          {"stress", {0.0}}};
}

}  // namespace

const char* to_string(Problem p) {
  return p == Problem::two_bar ? "two_bar" : "smooth_pulse";
}

void apply_method(nlohmann::json& scene, const MethodSpec& m) {
  scene["method"] = m.method;
  if (!m.update.empty()) scene["update"] = m.update;
  if (!m.flux.empty()) scene["flux"] = m.flux;
  nlohmann::json& t = scene["time"];
  t["integrator"] = m.integrator;
  if (m.courant_auto)
    t["courant"] = "auto";
  else
    t["courant"] = m.courant;
}

nlohmann::json two_bar_scene(int cells, const MethodSpec& m) {
  const double z = std::sqrt(young * density), v0 = 4e9 / (2 * z);
  nlohmann::json s = {
      {"dimension", 1},
      {"grid", {{"origin", {0.0}}, {"cell_size", {6.0 / cells}}, {"cells", {cells}}}},
      {"materials", steel()},
      {"bodies", {body(0, 3, v0, m.particles_per_cell), body(3, 6, -v0, m.particles_per_cell)}},
      {"boundaries", {{"xmin", {{"type", "free"}}}, {"xmax", {{"type", "free"}}}}},
      {"time", {{"end", 2.0 / wave_speed}}},
      {"exact", "bar"}};
  apply_method(s, m);
  return s;
}

nlohmann::json smooth_pulse_scene(int cells, const MethodSpec& m) {
  // sin^2 pulse of 0.3 m, tabulated finely enough (0.15 mm per point in space) that the kinks of
  // the linear interpolation stay below the errors of the finest grids.
  const double duration = 0.3 / wave_speed, amplitude = -1e8;
  const int points = 2000;
  nlohmann::json table = nlohmann::json::array();
  for (int k = 0; k <= points; ++k) {
    const double t = duration * k / points, s = std::sin(std::numbers::pi * k / points);
    table.push_back({t, amplitude * s * s});
  }
  nlohmann::json s = {
      {"dimension", 1},
      {"grid", {{"origin", {0.0}}, {"cell_size", {1.0 / cells}}, {"cells", {cells}}}},
      {"materials", steel()},
      {"bodies", {body(0, 1, 0.0, m.particles_per_cell)}},
      {"boundaries",
       {{"xmin", {{"type", "free"}}}, {"xmax", {{"type", "traction"}, {"value", table}}}}},
      {"time", {{"end", 0.8 / wave_speed}}},
      {"exact", "bar"}};
  apply_method(s, m);
  return s;
}

nlohmann::json scene_for(Problem p, int cells, const MethodSpec& m) {
  return p == Problem::two_bar ? two_bar_scene(cells, m) : smooth_pulse_scene(cells, m);
}

RunRow run_scene(const nlohmann::json& document, std::optional<double> energy_growth_limit,
                 double min_seconds) {
  using clock = std::chrono::steady_clock;
  const double nan = std::numeric_limits<double>::quiet_NaN();
  RunRow row;
  row.l2_error = row.max_error = row.energy_drift = nan;
  row.wall_seconds = std::numeric_limits<double>::infinity();
  std::unique_ptr<SimulationBase> sim;  // outside the try: a failed run still tells its step
  try {
    const scene::Scene scene = scene::parse_scene(document, "report");
    row.cells = scene.grid.cells[0];
    row.h = scene.grid.cell_size[0];
    double spent = 0;
    for (int repeat = 0; repeat < 5 && (repeat == 0 || spent < min_seconds); ++repeat) {
      // Set-up (operators, automatic time step analysis) is part of the cost of a run.
      const auto start = clock::now();
      sim = make_simulation(scene);
      const RunSummary s = sim->run();
      const double wall = std::chrono::duration<double>(clock::now() - start).count();
      spent += wall;
      row.wall_seconds = std::min(row.wall_seconds, wall);
      row.steps = s.steps;
      row.dt_min = s.dt_min;
      row.dt_max = s.dt_max;
      if (s.stress_errors) {
        row.l2_error = s.stress_errors->l2;
        row.max_error = s.stress_errors->max;
      }
      row.energy_drift =
          s.energy_initial > 0 ? (s.energy_final - s.energy_initial) / s.energy_initial : nan;
      row.warning = s.warnings.empty() ? "" : s.warnings.front();
    }
  } catch (const std::exception& e) {
    row.failure = e.what();
    if (sim) row.steps = sim->steps();
    return row;
  }
  if (!std::isfinite(row.energy_drift) && !std::isnan(row.energy_drift))
    row.failure = "energy not finite";
  else if (energy_growth_limit && row.energy_drift > *energy_growth_limit)
    row.failure = "energy grows";
  else if (std::isfinite(row.l2_error) || std::isnan(row.l2_error)) {
    // A relative error above 1 is no approximation at all: a blown-up run.
    if (row.l2_error > 1.0) row.failure = "relative L2 error above 1";
  } else
    row.failure = "error not finite";
  row.stable = row.failure.empty();
  return row;
}

}  // namespace dgmpm::report
