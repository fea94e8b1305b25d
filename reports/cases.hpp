#pragma once
// The runs a report is made of: scenes built in memory, run in-process through Simulation, and
// summarised as one row each (error, wall time, steps, energy drift, stability).

#include <nlohmann/json.hpp>

#include <optional>
#include <string>
#include <vector>

namespace dgmpm::report {

// One method and its settings: DGMPM (Euler or RK2, particles per cell, fixed or automatic
// Courant number) or MPM (variant and velocity update).
struct MethodSpec {
  std::string label;       // as shown in plots and tables
  std::string method;      // scene "method"
  std::string update;      // MPM: "flip" or "pic"; empty for DGMPM
  std::string integrator;  // "euler" or "rk2"
  int particles_per_cell = 1;
  bool courant_auto = false;
  double courant = 1.0;  // when not auto
  std::string flux;      // 2D DGMPM: "dcu" or "ctu"
};

// The two problems of the accuracy study.
enum class Problem { two_bar, smooth_pulse };
const char* to_string(Problem);

// Founding paper's two-bar impact on [0, 6] m with `cells` cells (a multiple of 6 keeps the body
// boundary and, at Courant 1, the final time on cell faces), compared at t = 2 m / c.
nlohmann::json two_bar_scene(int cells, const MethodSpec& m);
// Bar [0, 1] m at rest, free at x = 0, loaded at x = 1 by a smooth sin^2 compression pulse given
// as a time table of many points, compared at t = 0.8 m / c, before the pulse reaches x = 0.
nlohmann::json smooth_pulse_scene(int cells, const MethodSpec& m);
nlohmann::json scene_for(Problem p, int cells, const MethodSpec& m);

// Sets the time block of a scene from a method.
void apply_method(nlohmann::json& scene, const MethodSpec& m);

struct RunRow {
  std::string problem, label;
  int cells = 0;
  double h = 0;
  long steps = 0;
  double dt_min = 0, dt_max = 0;
  double wall_seconds = 0;             // best of the repeats
  double l2_error = 0, max_error = 0;  // relative stress errors; NaN when unavailable
  double energy_drift = 0;             // (E_end - E_0) / E_0
  bool stable = false;
  std::string failure;  // why not stable
  std::string warning;  // the run's first warning (above C*, over-full cell), if any
};

// Runs a scene; short runs are repeated (best time kept) so that timings are not just noise.
// Never throws for a failed run: the row says unstable and why. With free ends the exact energy
// is constant: a relative growth above `energy_growth_limit` (when given) flags an instability.
// DGMPM dissipates, so a tight limit fits it; MPM FLIP may gain a little energy without blowing up.
RunRow run_scene(const nlohmann::json& scene, std::optional<double> energy_growth_limit,
                 double min_seconds = 0.02);

}  // namespace dgmpm::report
