#pragma once
// The explicit time loop of a scene: DGMPM (Euler or RK2) or the MPM baseline on the same grid,
// particles and boundaries. Time steps land exactly on output times and on the end time.

#include "solver/problem.hpp"
#include "solver/scene.hpp"
#include "solver/time_step_control.hpp"

#include <dgmpm/discretisation.hpp>
#include <dgmpm/time_integration.hpp>

#include <memory>
#include <nlohmann/json.hpp>
#include <optional>
#include <string>
#include <vector>

namespace dgmpm {

struct ErrorNorms {
  double l1 = 0, l2 = 0, max = 0;  // relative, see relative_errors()
};

struct RunSummary {
  long steps = 0;
  double final_time = 0, dt_min = 0, dt_max = 0, wall_seconds = 0;
  double energy_initial = 0, energy_final = 0;
  std::optional<ErrorNorms> stress_errors, velocity_errors;
  int layouts_analysed = 0;
  std::vector<std::string> warnings;
  std::vector<std::string> files;
  nlohmann::json to_json() const;
};

struct RunOptions {
  std::optional<std::string> output_directory;  // overrides the scene's
  bool progress = false;                        // progress line on stderr
};

// Errors ||u_h - u||/||u|| with volume-weighted L1 and L2 norms and the max norm over
// particles. When the exact field vanishes at that time, the norms of `fallback` normalise
// instead (the run uses the other field times or over the impedance); when that vanishes too,
// errors are absolute.
ErrorNorms relative_errors(const Eigen::VectorXd& computed, const Eigen::VectorXd& exact,
                           const Eigen::VectorXd& volume, const Eigen::VectorXd& fallback);

class Simulation {
 public:
  explicit Simulation(const scene::Scene& scene);
  ~Simulation();
  Simulation(const Simulation&) = delete;
  Simulation& operator=(const Simulation&) = delete;

  const scene::Scene& scene() const { return scene_; }
  const BarProblem& problem() const { return problem_; }
  const Particles<1, ElasticBar::n_comp>& particles() const { return problem_.particles; }
  double time() const { return time_; }
  long steps() const { return steps_; }

  // Step length of the current configuration: from the scene's Courant number, or from the
  // stability analysis of the cells' layouts with "courant": "auto" (recomputed after moves).
  double stable_time_step() const { return dt_; }
  // DGMPM only (empty for MPM).
  const std::optional<TimeStepControl>& time_step_control() const { return time_control_; }
  // Set up: a fixed Courant number above the admissible one of some cell's layout. Any time: the
  // first cell holding more than a full cell's mass (see warn_if_overfull_cell).
  const std::vector<std::string>& warnings() const { return warnings_; }
  // One step of length dt; moves particles and rebuilds the operators when the scene asks.
  // Throws std::runtime_error naming the step, time, particle and cell on a non-finite state or
  // a particle leaving the grid.
  void step(double dt);
  // Steps to `t_end`, landing on it exactly.
  void advance_to(double t_end);
  // The whole scene: steps, outputs, summary.
  RunSummary run(const RunOptions& options = {});

  Eigen::VectorXd stress() const;
  Eigen::VectorXd velocity() const;
  // Kinetic and elastic energy of the particles (per unit cross-section).
  struct Energy {
    double kinetic = 0, elastic = 0;
    double total() const { return kinetic + elastic; }
  };
  Energy energy_parts() const;
  double energy() const { return energy_parts().total(); }
  // Requires an exact solution. Evaluated at the particles' initial positions: with moving
  // particles (small strain) fields are compared in the material coordinate.
  Eigen::VectorXd exact_stress(double t) const;
  Eigen::VectorXd exact_velocity(double t) const;

 private:
  struct Stepper;
  // One step toward `target`, shortened to land on it; returns its length, 0 once there.
  double step_towards(double target);
  void check_finite() const;
  void warn_if_above_admissible();
  void warn_if_overfull_cell(long step, double t);
  void write_particles(const std::string& path) const;

  scene::Scene scene_;
  BarProblem problem_;
  std::unique_ptr<Stepper> stepper_;
  Eigen::Matrix<double, 1, Eigen::Dynamic> reference_position_;  // initial positions
  std::optional<TimeStepControl> time_control_;
  std::vector<std::string> warnings_;
  double time_ = 0, dt_ = 0;
  long steps_ = 0;
  bool overfull_warned_ = false;
};

}  // namespace dgmpm
