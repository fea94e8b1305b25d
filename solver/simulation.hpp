#pragma once
// The explicit time loop of a scene: DGMPM (Euler or RK2, DCU or CTU) or the MPM baseline on the
// same grid, particles and boundaries. Time steps land exactly on output times and on the end
// time. Simulation<Physics> is the loop of one physics; make_simulation is the one place where
// a scene's dimension picks it.

#include "solver/blow_up_monitor.hpp"
#include "solver/communicator.hpp"
#include "solver/halo.hpp"
#include "solver/problem.hpp"
#include "solver/scene.hpp"
#include "solver/stepping_method.hpp"
#include "solver/time_step_control.hpp"

#include <dgmpm/physics/contract.hpp>
#include <dgmpm/stepper.hpp>

#include <chrono>
#include <csignal>
#include <cstdint>
#include <iosfwd>
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
  nlohmann::json run;  // what ran: scene, method, integrator, dimension, (flux), particles, cells
  // How the run ended: "completed", "failed" (an error stopped it: `reason`) or "interrupted" (a
  // signal: `reason`).
  std::string status = "completed", reason;
  long steps = 0;
  double final_time = 0, dt_min = 0, dt_max = 0;
  // wall = set-up (the problem, the operators, the first time step) + stepping (the time loop);
  // time_step: choosing steps (layouts analysed included), part of both.
  double wall_seconds = 0, setup_seconds = 0, stepping_seconds = 0, time_step_seconds = 0;
  double layout_analysis_seconds = 0;       // of time_step_seconds: analysing new layouts
  double courant_min = 0, courant_max = 0;  // c_max dt / h of the controlled steps
  double energy_initial = 0, energy_final = 0;
  // Materials that yield: the final energy's parts stored by hardening and dissipated.
  std::optional<double> energy_stored, energy_dissipated;
  double boundary_work = 0;  // work done on the body by boundary loads (traction, velocity)
  std::optional<ErrorNorms> stress_errors, velocity_errors;
  int layouts_analysed = 0;
  std::vector<std::string> warnings;
  std::vector<std::string> files;
  nlohmann::json to_json() const;
};

struct RunOptions {
  std::optional<std::string> output_directory;  // overrides the scene's
  bool progress = false;                        // progress line on stderr
  double progress_every = 10;  // seconds between progress lines when stderr is not a terminal
  bool overwrite =
      false;  // replace another scene's outputs in the directory (output::DirectoryClaim)
  // Checkpoints, written into the output directory as checkpoint_<step>.ckpt: every
  // `checkpoint_steps` steps and/or after each `checkpoint_seconds` of simulated time (0: never);
  // the newest `checkpoint_keep` are kept (0: all).
  long checkpoint_steps = 0;
  double checkpoint_seconds = 0;
  int checkpoint_keep = 0;
  // Set by a signal handler to the signal's number: the run stops after the current step (every
  // rank at the same step), writes its record and returns with status "interrupted".
  const volatile std::sig_atomic_t* stop = nullptr;
};

// Errors ||u_h - u|| / ||u|| over particles, u_p a column (the Euclidean norm of its components
// at each particle), with volume-weighted L1 and L2 norms and the max norm. When the exact field
// vanishes at that time, the norms of `fallback` normalise instead (the run uses the other
// field times or over the impedance); when that vanishes too, errors are absolute.
ErrorNorms relative_errors(const Eigen::MatrixXd& computed, const Eigen::MatrixXd& exact,
                           const Eigen::VectorXd& volume, const Eigen::MatrixXd& fallback);

// What the command line needs of a run, whatever its physics.
class SimulationBase {
 public:
  virtual ~SimulationBase() = default;
  virtual const scene::Scene& scene() const = 0;
  virtual const std::vector<std::string>& warnings() const = 0;
  virtual RunSummary run(const RunOptions& options = {}) = 0;
  // The summary of the last run(), also when it failed (status "failed", with the reason; in a
  // distributed run only the numbers this rank knows without the others).
  virtual const std::optional<RunSummary>& last_summary() const = 0;
  virtual int num_particles() const = 0;
  virtual int num_cells() const = 0;
  virtual long steps() const = 0;   // taken so far
  virtual double time() const = 0;  // simulated so far (a restart's: its checkpoint's)
  // Continues from a checkpoint written by run(): the next run() ends bit for bit as the run that
  // wrote it would have. Throws scene::SceneError for a checkpoint of another scene or version.
  virtual void restore(const std::string& checkpoint) = 0;
};

template <class Physics>
class Simulation final : public SimulationBase {
 public:
  static constexpr int dim = Physics::dim;
  static constexpr int ncomp = Physics::n_comp;
  using ParticleSet = ParticlesOf<Physics>;
  using Field = Eigen::Matrix<double, ncomp, Eigen::Dynamic>;

  // With `ranks` of more than one rank: this rank's part of a distributed run (docs/distributed.md;
  // DGMPM only). Every rank is given the same scene; calls are then collective.
  explicit Simulation(const scene::Scene& scene, Communicator* ranks = nullptr);
  // The same, its set-up time counted from `start` (when the caller began reading the scene).
  Simulation(const scene::Scene& scene, Communicator* ranks,
             std::chrono::steady_clock::time_point start);
  ~Simulation() override;
  Simulation(const Simulation&) = delete;
  Simulation& operator=(const Simulation&) = delete;

  const scene::Scene& scene() const override { return scene_; }
  const Problem<Physics>& problem() const { return problem_; }
  // This rank's particles: all of them in a serial run; in a distributed one, the owned ones
  // (the first owned_particles()) then the ghosts.
  const ParticleSet& particles() const { return problem_.particles; }
  int owned_particles() const { return halo_ ? halo_->owned() : problem_.particles.size(); }
  // The particles' positions in the serial run's arrays (distributed runs only).
  const Halo<ParticleSet>* halo() const { return halo_.get(); }
  int num_particles() const override { return total_particles_; }
  int num_cells() const override { return total_cells_; }
  double time() const override { return time_; }
  long steps() const override { return steps_; }

  // Step length of the current configuration: from the scene's Courant number, or from the
  // stability analysis of the cells' layouts with "courant": "auto" (recomputed after moves).
  double stable_time_step() const { return method_->time_step(); }
  // DGMPM only (null for MPM).
  const TimeStepControl<Physics>* time_step_control() const { return method_->time_step_control(); }
  // Set up: a fixed Courant number above the admissible one of some cell's layout. Any time: the
  // first cell holding more than a full cell's mass (DgmpmMethod::warn_if_overfull_cell).
  const std::vector<std::string>& warnings() const override { return warnings_; }
  // One step of length dt; moves particles and rebuilds the operators when the scene asks.
  // Throws std::runtime_error naming the step, time, particle and cell on a non-finite state or
  // a particle leaving the grid.
  void step(double dt);
  // Steps to `t_end`, landing on it exactly.
  void advance_to(double t_end);
  // The whole scene: steps, outputs, summary.
  RunSummary run(const RunOptions& options = {}) override;
  const std::optional<RunSummary>& last_summary() const override { return last_summary_; }
  void restore(const std::string& checkpoint) override;

  // Physical state (sigma, v) of every (owned) particle: 1D (sigma, v); 2D (sigma_xx, sigma_yy,
  // sigma_xy, v_x, v_y).
  Field physical_state() const;
  Eigen::VectorXd stress() const requires(dim == 1) { return physical_state().row(0).transpose(); }
  Eigen::VectorXd velocity() const requires(dim == 1) {
    return physical_state().row(1).transpose();
  }
  // Kinetic and elastic energy of the particles (per unit cross-section in 1D, per unit
  // thickness in 2D).
  // With materials that yield, also the energy stored by hardening and the energy dissipated so
  // far (zero otherwise), which the total includes.
  struct Energy {
    double kinetic = 0, elastic = 0, stored = 0, dissipated = 0;
    double total() const { return kinetic + elastic + stored + dissipated; }
  };
  static_assert(physics::HasEnergy<Physics>, "the solver reports the particles' energy");
  static constexpr bool dissipative = physics::Dissipative<Physics>;
  // Wave speeds that change with the state (finite strain): a new time step every step.
  static constexpr bool state_dependent_speed = physics::StateDependentSpeed<Physics>;
  // Output columns the physics derives from a particle (none for elastic physics).
  static constexpr int derived_count = [] {
    if constexpr (physics::DerivedOutputs<Physics>)
      return static_cast<int>(Physics::derived_names.size());
    else
      return 0;
  }();
  Energy energy_parts() const;
  double energy() const { return energy_parts().total(); }
  // Work done on the body by the boundary loads so far (DGMPM, trapezoidal in time; 0 for MPM).
  double boundary_work() const { return method_->boundary_work().value_or(0.0); }
  // Requires an exact solution; owned particles. Evaluated at the particles' initial positions:
  // with moving particles (small strain) fields are compared in the material coordinate.
  Field exact_state(double t) const;
  Eigen::VectorXd exact_stress(double t) const requires(dim == 1) {
    return exact_state(t).row(0).transpose();
  }
  Eigen::VectorXd exact_velocity(double t) const requires(dim == 1) {
    return exact_state(t).row(1).transpose();
  }

 private:
  // One step toward `target`, shortened to land on it; returns its length, 0 once there.
  double step_towards(double target);
  void check_finite() const;
  void check_growth();
  Energy particle_energy(int i) const;
  void warn_about_untouched_loads();
  void write_particles(const std::string& path) const;
  void write_vtu(std::size_t k, const std::string& directory, const std::string& name) const;
  void distribute(Communicator& ranks);
  bool root() const { return !halo_ || halo_->subdomain().rank() == 0; }
  const Grid<dim>& full_grid() const {
    return halo_ ? halo_->subdomain().full_grid() : problem_.grid;
  }
  // The full grid's index of local cell c (a window's cells are numbered from its corner).
  int full_cell(int c) const {
    return halo_ ? full_grid().flatten(halo_->subdomain().full_cell(c)) : c;
  }
  void write_checkpoint(const std::string& path) const;

  // run() in parts: its files (RunRecord: simulation_impl.hpp), outputs, checkpoints, summary.
  struct RunRecord;
  std::vector<std::string> checkpoint_files(const std::string& name) const;
  std::string vtu_file(std::size_t k) const;
  void claim_directory(RunRecord& record, bool resumed);
  int copy_earlier_outputs(const std::string& directory) const;
  void open_history(RunRecord& record, bool resumed);
  void commit_history(RunRecord& record) const;
  void write_history(std::ostream* out, double dt, const Energy& e) const;
  double expected_steps() const;
  void write_output(RunRecord& record);
  bool output_due(const RunRecord& record) const;
  bool checkpoint_due(const RunRecord& record) const;
  void take_checkpoint(RunRecord& record);
  double next_checkpoint_time(const RunRecord& record) const;
  RunSummary summarise() const;
  void add_errors(RunSummary& summary) const;
  void write_index(const RunRecord& record) const;
  void close_record(RunRecord& record, RunSummary& summary);
  void record_failure(RunRecord& record, double stepping_seconds, const std::string& reason);
  int stop_signal(const RunOptions& options) const;
  int time_loop(RunRecord& record, bool progress);

  // What run() has done so far: a checkpoint records it, a restart continues from it.
  struct Progress {
    std::size_t outputs = 0;                             // particle outputs written
    std::vector<std::pair<double, std::string>> series;  // (time, .vtu file name)
    std::vector<std::string> index_rows;                 // outputs.csv rows
    std::vector<std::string> files;                      // particle files written (names)
    std::vector<std::string> checkpoints;                // kept checkpoint files (names)
    double dt_min = 0, dt_max = 0;                       // of the controlled steps
    double courant_min = 0, courant_max = 0;             // c_max dt / h of the same
    std::uint64_t history_bytes = 0, history_hash = 0;   // energy.csv at the checkpoint
    long checkpoint_step = -1;                           // step of the last checkpoint
  };
  Progress progress_;
  // energy_parts' sums per block of kEnergyBlock particles (kept: no allocation per step).
  static constexpr int kEnergyBlock = 16384;
  mutable std::vector<Energy> energy_blocks_;
  std::optional<RunSummary> last_summary_;
  std::string restored_from_;  // the checkpoint a restart began at
  std::string restored_directory_;

  scene::Scene scene_;
  Problem<Physics> problem_;
  std::unique_ptr<Halo<ParticleSet>> halo_;  // distributed runs
  int total_particles_ = 0, total_cells_ = 0;
  double setup_seconds_ = 0;  // the constructor's wall time
  // Of the materials the particles carry (at their current states where speeds change with the
  // state), and its value at the start of the last step.
  double max_speed_ = 0, step_speed_ = 0;
  double cell_size() const { return problem_.grid.cell_size.minCoeff(); }
  double courant_per_dt() const { return max_speed_ / cell_size(); }
  std::vector<std::string> warnings_;
  double time_ = 0;
  long steps_ = 0;
  // DGMPM or MPM: the step, the time step, the loads' work (declared after what it refers to).
  std::unique_ptr<SteppingMethod<Physics>> method_;
  double dt() const { return method_->time_step(); }
  BlowUpMonitor blow_up_;
};

using BarSimulation = Simulation<ElasticBar>;
using PlaneStrainSimulation = Simulation<PlaneStrain>;

// Energies are per unit cross-section in 1D, per unit thickness in 2D.
constexpr const char* energy_unit(int dim) {
  return dim == 1 ? "J/m^2" : (dim == 2 ? "J/m" : "J");
}

// The run-time dispatch on the scene's dimension (and so its physics).
// `ranks`: see Simulation's constructor.
std::unique_ptr<SimulationBase> make_simulation(const scene::Scene& scene,
                                                Communicator* ranks = nullptr);

}  // namespace dgmpm
