#pragma once
// The method a run steps with, behind one interface: DGMPM (DgmpmMethod: the stepper, the time
// step control, the work of the loads) or the MPM baseline (MpmMethod). Simulation's time loop,
// outputs and checkpoints see only SteppingMethod; each method keeps its own state and saves and
// restores it in the checkpoint's header.

#include "solver/communicator.hpp"
#include "solver/frozen_spectrum.hpp"
#include "solver/halo.hpp"
#include "solver/mpm.hpp"
#include "solver/problem.hpp"
#include "solver/scene.hpp"
#include "solver/time_step_control.hpp"

#include <dgmpm/physics/contract.hpp>
#include <dgmpm/stepper.hpp>

#include <cmath>
#include <iomanip>
#include <limits>
#include <memory>
#include <nlohmann/json.hpp>
#include <optional>
#include <sstream>
#include <stability/layout.hpp>
#include <string>
#include <vector>

namespace dgmpm {

struct RunSummary;

// The stepper options a scene asks for (one definition for every caller).
StepperOptions stepper_options(const scene::Scene& scene);

inline std::string format_step(long step, double t) {
  std::ostringstream s;
  s << "step " << step << ", t = " << std::setprecision(10) << t;
  return s.str();
}

// What a method reads and updates of its run: the scene, the problem (this rank's window once
// distributed), the halo of a distributed run, the run's warnings and the particles' largest wave
// speed (it changes with the state in finite strain; the method that chooses the step updates it).
template <class Physics>
struct RunParts {
  const scene::Scene& scene;
  Problem<Physics>& problem;
  const std::unique_ptr<Halo<ParticlesOf<Physics>>>& halo;
  std::vector<std::string>& warnings;
  double& max_speed;
};

template <class Physics>
class SteppingMethod {
 public:
  virtual ~SteppingMethod() = default;
  // Before a distributed run keeps this rank's window: throws scene::SceneError where the scene
  // asks for what `count` ranks cannot do. After: the method rebuilds itself on the window.
  virtual void check_distributable(const std::string& count) const = 0;
  virtual void distributed() = 0;
  // Step number `step` (counted from 1) from t to t + dt: the particles' new states and, when the
  // scene asks, positions (ghosts brought up to date). Returns whether every new state is known
  // finite. Throws ParticleOutsideGrid.
  virtual bool step(long step, double t, double dt) = 0;
  // After step `step`, now at t (the particles known finite): the next step's length and the
  // loads' work.
  virtual void after_step(long step, double t, double dt) = 0;
  virtual double time_step() const = 0;  // the current step length
  // The loads' work so far as the blow-up check and the progress line count it; the reported
  // boundary work (summary, energy.csv), where the method balances its energy exactly.
  virtual double load_work() const = 0;
  virtual std::optional<double> boundary_work() const = 0;
  virtual const TimeStepControl<Physics>* time_step_control() const { return nullptr; }
  virtual void summarise(RunSummary&) const {}
  // Their own keys of the checkpoint's header; restore runs once the particles are restored.
  virtual void save(nlohmann::json& header) const = 0;
  virtual void restore(const nlohmann::json& header) = 0;
};

// A state with no real wave speed stops the run, naming its (owned) particle: after a time step
// came out NaN on some rank (`here`: on this one).
template <class Physics>
void check_hyperbolic(const RunParts<Physics>& run, int owned, bool here, long step, double t) {
  if constexpr (physics::StateDependentSpeed<Physics>) {
    constexpr int dim = Physics::dim;
    const auto& halo = run.halo;
    if (!(halo ? halo->comm().min(here ? 0.0 : 1.0) == 0.0 : here)) return;
    const auto& p = run.problem.particles;
    const Grid<dim>& grid = halo ? halo->subdomain().full_grid() : run.problem.grid;
    for (int i = 0; i < owned; ++i) {
      const auto& m = run.problem.materials[p.material[i]];
      if (Physics::state_wave_speed(p.state.col(i), m) >= 0) continue;
      const typename Physics::State s = Physics::physical(p.state.col(i), m);
      Eigen::Matrix<double, dim, 1> xi;
      std::ostringstream o;
      o << format_step(step, t) << ": particle " << p.id[i]
        << " has left its material's hyperbolic range (its acoustic tensor is not positive "
           "definite: no real wave speed) at X = "
        << p.position.col(i).transpose() << " (cell " << grid.locate(p.position.col(i), xi)
        << ") with ";
      for (int k = 0; k < Physics::n_comp; ++k)
        o << (k ? ", " : "") << Physics::state_names[k] << " = " << std::setprecision(9) << s[k];
      o << "; the equations are no longer well posed there (a compression too strong for the "
           "law, e.g. Saint Venant-Kirchhoff compressed below F = 1/sqrt(3) in uniaxial strain, "
           "sooner in plane strain, where oblique waves fail first)";
      throw std::runtime_error(o.str());
    }
    throw RankStopped("a particle left its hyperbolic range (another rank names it)");
  } else {
    (void)run, (void)owned, (void)here, (void)step, (void)t;
  }
}

template <class Physics>
class DgmpmMethod final : public SteppingMethod<Physics> {
 public:
  static constexpr int dim = Physics::dim;
  static constexpr bool state_dependent_speed = physics::StateDependentSpeed<Physics>;

  // Set up on the whole scene: the stepper, the first time step and the set-up's warnings.
  explicit DgmpmMethod(const RunParts<Physics>& run);

  void check_distributable(const std::string& count) const override {
    const scene::Scene& scene = run_.scene;
    if (scene.time.check_scene_every > 0)
      throw scene::SceneError(scene.source + ": time.check_scene_every: value " +
                              std::to_string(scene.time.check_scene_every) +
                              " is not available on " + count +
                              " (the whole scene's operator is analysed on one rank); allowed: 0");
  }
  void distributed() override {
    auto& problem = run_.problem;
    stepper_ = std::make_unique<Stepper<Physics>>(problem.grid, problem.boundaries,
                                                  stepper_options(run_.scene));
    stepper_->rebuild(problem.particles, problem.materials);
    if (loaded_) power_ = load_power(0.0);
  }
  bool step(long step, double t, double dt) override {
    auto& particles = run_.problem.particles;
    if (run_.scene.particles_move) {
      // Each particle moves with its new velocity in the sweep that interpolates it: no pass of
      // its own over the particles, and on the step's threads.
      const auto constitutive =
          physics_particle_step<Physics>(particles, run_.problem.materials, dt);
      const bool finite =
          stepper_->step(particles.state, particles.mass, t, dt, [&](int p, auto&& q) {
            constitutive(p, q);
            particles.position.col(p) += dt * q.template bottomRows<dim>();
          });
      if (run_.halo) run_.halo->migrate(particles);
      stepper_->rebuild(particles, run_.problem.materials);
      if (!overfull_warned_ && run_.scene.formulation == Formulation::paper)
        warn_if_overfull_cell(step, t + dt);
      return finite;
    }
    const bool finite = stepper_->step(particles, run_.problem.materials, t, dt);
    if (run_.halo) run_.halo->exchange_states(particles);
    return finite;
  }
  void after_step(long step, double t, double dt) override {
    // A new step where the layouts (moving particles, automatic step) or the speeds (finite
    // strain) have changed.
    if (run_.scene.particles_move ? time_control_->automatic() : state_dependent_speed)
      choose_time_step(step, t);
    if (loaded_) {
      const double power = load_power(t);
      work_ += 0.5 * dt * (power_ + power);
      power_ = power;
    }
  }
  double time_step() const override { return dt_; }
  double load_work() const override { return work_; }
  std::optional<double> boundary_work() const override { return work_; }
  const TimeStepControl<Physics>* time_step_control() const override { return &*time_control_; }
  void summarise(RunSummary& summary) const override;
  void save(nlohmann::json& header) const override;
  void restore(const nlohmann::json& header) override;

 private:
  const Grid<dim>& full_grid() const {
    return run_.halo ? run_.halo->subdomain().full_grid() : run_.problem.grid;
  }
  int full_cell(int c) const {
    return run_.halo ? full_grid().flatten(run_.halo->subdomain().full_cell(c)) : c;
  }
  int owned() const { return run_.halo ? run_.halo->owned() : run_.problem.particles.size(); }
  double load_power(double t) const;
  void choose_time_step(long step, double t);
  void check_scene(long step, double t);
  void warn_if_above_admissible();
  void warn_if_overfull_cell(long step, double t);

  RunParts<Physics> run_;
  std::unique_ptr<Stepper<Physics>> stepper_;
  std::optional<TimeStepControl<Physics>> time_control_;
  double dt_ = 0, work_ = 0, power_ = 0;
  bool loaded_ = false;  // some boundary does work (traction or velocity)
  bool overfull_warned_ = false;
  double scene_guard_factor_ = 1.0;  // what the last scene check scaled the automatic dt by
  bool scene_guard_warned_ = false;
};

// The MPM baseline: a fixed Courant number over the particles' largest speed, one rank.
template <class Physics>
class MpmMethod final : public SteppingMethod<Physics> {
 public:
  explicit MpmMethod(const RunParts<Physics>& run);

  void check_distributable(const std::string& count) const override {
    const scene::Scene& scene = run_.scene;
    throw scene::SceneError(scene.source + ": method: value \"" + scene::to_string(scene.method) +
                            "\" runs on one rank; allowed on " + count + ": \"dgmpm\"");
  }
  void distributed() override {}
  bool step(long, double t, double dt) override {
    return mpm_.step(run_.problem.particles, t, dt, run_.scene.particles_move);
  }
  void after_step(long step, double t, double) override {
    if constexpr (physics::StateDependentSpeed<Physics>) {  // C h / c at the particles' new speeds
      run_.max_speed = run_.problem.max_wave_speed();
      dt_ = run_.scene.time.courant * run_.problem.grid.cell_size.minCoeff() / run_.max_speed;
      check_hyperbolic(run_, run_.problem.particles.size(), std::isnan(dt_), step, t);
    } else {
      (void)step, (void)t;
    }
  }
  double time_step() const override { return dt_; }
  double load_work() const override { return mpm_.load_work(); }
  // Estimated from the nodal forces and velocities, not balanced against the particles' energy
  // (0 for 1D tractions): not reported.
  std::optional<double> boundary_work() const override { return std::nullopt; }
  void save(nlohmann::json& header) const override;
  void restore(const nlohmann::json& header) override;

 private:
  RunParts<Physics> run_;
  double dt_ = 0;
  Mpm<Physics> mpm_;
};

// The scene's method, set up on the whole scene.
template <class Physics>
std::unique_ptr<SteppingMethod<Physics>> make_method(const RunParts<Physics>& run) {
  switch (run.scene.method) {
    case scene::Method::dgmpm:
      return std::make_unique<DgmpmMethod<Physics>>(run);
    case scene::Method::mpm_usl:
    case scene::Method::mpm_usf:
    case scene::Method::mpm_musl:
      return std::make_unique<MpmMethod<Physics>>(run);
  }
  throw std::logic_error("make_method: unknown method");
}

}  // namespace dgmpm
