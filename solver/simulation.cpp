#include "solver/simulation.hpp"

#include "solver/mpm.hpp"
#include "solver/output.hpp"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <iomanip>
#include <iostream>
#include <numeric>
#include <sstream>
#include <stability/layout.hpp>
#include <unistd.h>
#include <variant>

namespace dgmpm {

using Physics = ElasticBar;

struct Simulation::Stepper {
  // DGMPM: the operators of the current configuration and one integrator (no RK2 buffers for
  // Euler).
  Discretisation<Physics> disc;
  std::unique_ptr<DGOperator<Physics>> op;
  std::variant<std::monostate, ForwardEuler<Physics>, HeunRK2<Physics>> integrator;
  // MPM baseline.
  std::unique_ptr<Mpm<1>> mpm;
};

namespace {

MpmVariant mpm_variant(scene::Method m) {
  switch (m) {
    case scene::Method::mpm_usf:
      return MpmVariant::usf;
    case scene::Method::mpm_musl:
      return MpmVariant::musl;
    default:
      return MpmVariant::usl;
  }
}

// Particles sorted by cell so that the per-cell loops read contiguous memory.
void sort_by_cell(const Grid<1>& grid, Particles<1, Physics::n_comp>& particles) {
  std::vector<int> cell(particles.size());
  Eigen::Matrix<double, 1, 1> xi;
  for (int p = 0; p < particles.size(); ++p) cell[p] = grid.locate(particles.position.col(p), xi);
  std::vector<int> order(particles.size());
  std::iota(order.begin(), order.end(), 0);
  std::stable_sort(order.begin(), order.end(), [&](int a, int b) { return cell[a] < cell[b]; });
  particles.permute(order);
}

std::string format_step(long step, double t) {
  std::ostringstream s;
  s << "step " << step << ", t = " << std::setprecision(10) << t;
  return s.str();
}

}  // namespace

nlohmann::json RunSummary::to_json() const {
  nlohmann::json j;
  j["steps"] = steps;
  j["final_time"] = final_time;
  j["dt_min"] = dt_min;
  j["dt_max"] = dt_max;
  j["wall_seconds"] = wall_seconds;
  j["energy_initial"] = energy_initial;
  j["energy_final"] = energy_final;
  if (stress_errors && velocity_errors) {
    const auto norms = [](const ErrorNorms& e) {
      return nlohmann::json{{"l1", e.l1}, {"l2", e.l2}, {"max", e.max}};
    };
    j["errors"] = {{"stress", norms(*stress_errors)}, {"velocity", norms(*velocity_errors)}};
  }
  j["layouts_analysed"] = layouts_analysed;
  j["warnings"] = warnings;
  j["files"] = files;
  return j;
}

ErrorNorms relative_errors(const Eigen::VectorXd& computed, const Eigen::VectorXd& exact,
                           const Eigen::VectorXd& volume, const Eigen::VectorXd& fallback) {
  const Eigen::ArrayXd e = (computed - exact).array().abs();
  const auto norms = [&](const Eigen::ArrayXd& u) {
    return ErrorNorms{(volume.array() * u).sum(), std::sqrt((volume.array() * u.square()).sum()),
                      u.size() ? u.maxCoeff() : 0.0};
  };
  const ErrorNorms err = norms(e), ref = norms(exact.array().abs()),
                   alt = norms(fallback.array().abs());
  const auto scale = [](double r, double a) { return r > 0 ? r : (a > 0 ? a : 1.0); };
  return {err.l1 / scale(ref.l1, alt.l1), err.l2 / scale(ref.l2, alt.l2),
          err.max / scale(ref.max, alt.max)};
}

Simulation::Simulation(const scene::Scene& scene)
    : scene_(scene), problem_(make_bar_problem(scene)), stepper_(std::make_unique<Stepper>()) {
  sort_by_cell(problem_.grid, problem_.particles);
  reference_position_ = problem_.particles.position;
  const double h = problem_.grid.cell_size.minCoeff();
  if (scene_.method == scene::Method::dgmpm) {
    stepper_->disc.set_fill_correction(scene_.fill_correction);
    stepper_->disc.build(problem_.grid, problem_.particles, problem_.materials);
    stepper_->op =
        std::make_unique<DGOperator<Physics>>(problem_.grid, stepper_->disc, problem_.boundaries);
    if (scene_.time.integrator == scene::Integrator::rk2)
      stepper_->integrator.emplace<HeunRK2<Physics>>();
    else
      stepper_->integrator.emplace<ForwardEuler<Physics>>();
    time_control_.emplace(scene_.time, scene_.particles_move);
    dt_ = time_control_->time_step(stepper_->disc, problem_.particles, h);
    if (!time_control_->automatic()) warn_if_above_admissible();
    if (!scene_.fill_correction) warn_if_overfull_cell(0, 0.0);
  } else {
    if (scene_.time.courant_auto)
      throw scene::SceneError(scene_.source +
                              ": time.courant: value \"auto\" is not available for method \"" +
                              scene::to_string(scene_.method) +
                              "\"; allowed: a positive number (the stability analysis is DGMPM's)");
    dt_ = scene_.time.courant * h / problem_.max_wave_speed();
    stepper_->mpm = std::make_unique<Mpm<1>>(problem_.grid, problem_.boundaries, problem_.materials,
                                             mpm_variant(scene_.method), scene_.update);
  }
}

Simulation::~Simulation() = default;

void Simulation::warn_if_above_admissible() {
  const auto limit = time_control_->smallest_admissible(stepper_->disc, problem_.particles,
                                                        problem_.grid.cell_volume());
  if (!(scene_.time.courant > limit.courant * (1 + 1e-9))) return;
  std::ostringstream s;
  s << "Courant number " << scene_.time.courant << " is above the admissible "
    << std::setprecision(6) << limit.courant << " (" << scene::to_string(scene_.time.criterion)
    << ", " << scene::to_string(scene_.time.integrator) << ") of the layout of cell " << limit.cell
    << " (positions " << stability::describe(limit.layout.positions) << ", masses "
    << stability::describe(limit.layout.masses) << (limit.fill < 1 ? ", fill " : "");
  if (limit.fill < 1) s << limit.fill;
  s << "): the run may be unstable";
  warnings_.push_back(s.str());
}

// A cell whose particles carry more than rho times its volume (moving particles piling up) breaks
// the scheme's consistency: the pseudo-stiffness term scales with the cell's mass, the face fluxes
// do not, so a constant state changes at a rate (fill - 1) F / (rho h) there, however small dt is.
// No time step restores monotonicity then; the run says so once, naming where it began (unless
// the scene asks for the fill correction, which removes the cause).
void Simulation::warn_if_overfull_cell(long step, double t) {
  const auto& disc = stepper_->disc;
  const double volume = problem_.grid.cell_volume();
  for (int c = 0; c < disc.num_cells(); ++c) {
    if (!disc.occupied(c)) continue;
    const double fill = TimeStepControl::fill(disc, c, volume);
    if (fill <= 1 + 1e-6) continue;
    std::ostringstream s;
    s << format_step(step, t) << ": cell " << c << " holds " << std::setprecision(6) << fill
      << " times a full cell's mass; the operators do not preserve constant states in an "
         "over-full cell, so new extrema can appear whatever the time step (\"fill_correction\": "
         "true restores them)";
    warnings_.push_back(s.str());
    overfull_warned_ = true;
    return;
  }
}

void Simulation::step(double dt) {
  auto& particles = problem_.particles;
  try {
    if (stepper_->mpm) {
      stepper_->mpm->step(particles, time_, dt, scene_.particles_move);
    } else {
      std::visit(
          [&](auto& integrator) {
            if constexpr (!std::is_same_v<std::decay_t<decltype(integrator)>, std::monostate>)
              integrator.step(*stepper_->op, particles.state, particles.mass, time_, dt);
          },
          stepper_->integrator);
      if (scene_.particles_move) {
        particles.position.row(0) += dt * particles.state.row(Physics::velocity);
        stepper_->disc.build(problem_.grid, particles, problem_.materials);
        if (!overfull_warned_ && !scene_.fill_correction)
          warn_if_overfull_cell(steps_ + 1, time_ + dt);
        if (time_control_->automatic())
          dt_ = time_control_->time_step(stepper_->disc, particles,
                                         problem_.grid.cell_size.minCoeff());
      }
    }
  } catch (const ParticleOutsideGrid& e) {
    throw std::runtime_error(format_step(steps_ + 1, time_ + dt) + ": " + e.what() + " [" +
                             std::to_string(problem_.grid.origin[0]) + ", " +
                             std::to_string(problem_.grid.upper(0)) + "]");
  }
  time_ += dt;
  ++steps_;
  check_finite();
}

void Simulation::check_finite() const {
  const auto& particles = problem_.particles;
  if (particles.state.allFinite()) return;
  for (int p = 0; p < particles.size(); ++p) {
    if (particles.state.col(p).allFinite() && particles.position.col(p).allFinite()) continue;
    Eigen::Matrix<double, 1, 1> xi;
    const int cell = problem_.grid.locate(particles.position.col(p), xi);
    std::ostringstream s;
    s << format_step(steps_, time_) << ": non-finite state on particle " << particles.id[p]
      << " (x = " << particles.position(0, p) << ", cell " << cell
      << "); the run is unstable: lower the Courant number";
    throw std::runtime_error(s.str());
  }
}

double Simulation::step_towards(double target) {
  const double remaining = target - time_;
  if (remaining <= 1e-12 * dt_) {
    time_ = std::max(time_, target);
    return 0.0;
  }
  // The last step absorbs round-off rather than leaving a sliver step behind.
  const bool last = remaining <= dt_ * (1 + 1e-9);
  const double dt = last ? remaining : dt_;
  step(dt);
  if (last) time_ = target;
  return dt;
}

void Simulation::advance_to(double t_end) {
  while (step_towards(t_end) > 0.0) {
  }
}

Eigen::VectorXd Simulation::stress() const {
  const auto& p = problem_.particles;
  Eigen::VectorXd s(p.size());
  for (int i = 0; i < p.size(); ++i)
    s[i] = Physics::stress_of(p.state.col(i), problem_.materials[p.material[i]].density);
  return s;
}

Eigen::VectorXd Simulation::velocity() const {
  return problem_.particles.state.row(Physics::velocity).transpose();
}

Simulation::Energy Simulation::energy_parts() const {
  const auto& p = problem_.particles;
  Energy e;
  for (int i = 0; i < p.size(); ++i) {
    e.kinetic += p.mass[i] * Physics::kinetic_energy_per_mass(p.state.col(i));
    e.elastic += p.mass[i] * Physics::elastic_energy_per_mass(p.state.col(i),
                                                              problem_.materials[p.material[i]]);
  }
  return e;
}

Eigen::VectorXd Simulation::exact_stress(double t) const {
  const auto& p = problem_.particles;
  Eigen::VectorXd s(p.size());
  for (int i = 0; i < p.size(); ++i) s[i] = problem_.exact->stress(reference_position_(0, i), t);
  return s;
}

Eigen::VectorXd Simulation::exact_velocity(double t) const {
  const auto& p = problem_.particles;
  Eigen::VectorXd v(p.size());
  for (int i = 0; i < p.size(); ++i) v[i] = problem_.exact->velocity(reference_position_(0, i), t);
  return v;
}

void Simulation::write_particles(const std::string& path) const {
  const auto sigma = stress();
  const auto v = velocity();
  std::optional<Eigen::VectorXd> es, ev;
  if (problem_.exact) es = exact_stress(time_), ev = exact_velocity(time_);
  const auto& p = problem_.particles;
  output::write_atomically(path, [&](std::ostream& out) {
    out << "id,x,mass,stress,velocity" << (es ? ",exact_stress,exact_velocity" : "") << '\n';
    for (int i = 0; i < p.size(); ++i) {
      out << p.id[i] << ',' << p.position(0, i) << ',' << p.mass[i] << ',' << sigma[i] << ','
          << v[i];
      if (es) out << ',' << (*es)[i] << ',' << (*ev)[i];
      out << '\n';
    }
  });
}

RunSummary Simulation::run(const RunOptions& options) {
  using clock = std::chrono::steady_clock;
  const auto start = clock::now();
  RunSummary summary;
  summary.energy_initial = energy();
  summary.dt_min = summary.dt_max = dt_;

  const std::string directory = options.output_directory.value_or(scene_.output.directory);
  const bool writes = !directory.empty();
  std::vector<double> targets;
  if (writes) {
    output::create_directories(directory);
    targets = scene_.output.times;
  }
  targets.push_back(scene_.time.end);
  std::sort(targets.begin(), targets.end());
  targets.erase(std::unique(targets.begin(), targets.end()), targets.end());

  output::StreamedFile history;
  const auto& particles = problem_.particles;
  const auto write_history = [&](double dt) {
    const Energy e = energy_parts();
    history.stream() << steps_ << ',' << time_ << ',' << dt << ',' << e.kinetic << ',' << e.elastic
                     << ',' << e.total() << '\n';
  };
  if (writes) {
    history = output::StreamedFile(directory + "/energy.csv");
    history.stream() << "step,time,dt,kinetic,elastic,total\n";
    write_history(0.0);
  }

  const bool progress = options.progress && ::isatty(STDERR_FILENO);
  auto last_report = start;
  const double t_end = scene_.time.end;
  int output_index = 0;
  for (double target : targets) {
    for (double controlled = dt_, dt; (dt = step_towards(target)) > 0.0; controlled = dt_) {
      // The range of the controlled step; steps shortened to land on a time are not counted.
      summary.dt_min = std::min(summary.dt_min, controlled);
      summary.dt_max = std::max(summary.dt_max, controlled);
      if (writes) write_history(dt);
      if (progress) {
        const auto now = clock::now();
        const double elapsed = std::chrono::duration<double>(now - start).count();
        if (elapsed > 2.0 && now - last_report > std::chrono::milliseconds(500)) {
          last_report = now;
          const double left = elapsed * (t_end - time_) / time_;
          std::fprintf(stderr, "\rstep %ld  t = %.6g / %.6g  (%.1f%%)  about %.0f s left   ",
                       steps_, time_, t_end, 100.0 * time_ / t_end, left);
        }
      }
    }
    if (writes && std::find(scene_.output.times.begin(), scene_.output.times.end(), target) !=
                      scene_.output.times.end()) {
      char name[64];
      std::snprintf(name, sizeof name, "/particles_%03d.csv", output_index++);
      write_particles(directory + name);
      summary.files.push_back(directory + name);
    }
  }
  if (progress) std::fprintf(stderr, "\r%78s\r", "");

  summary.steps = steps_;
  summary.final_time = time_;
  summary.warnings = warnings_;
  if (time_control_) summary.layouts_analysed = time_control_->layouts_analysed();
  summary.energy_final = energy();
  if (problem_.exact) {
    const Eigen::VectorXd& vol = particles.volume;
    // Where one exact field vanishes, the other one, through the impedance, sets the scale.
    const double z = problem_.exact->impedance();
    const Eigen::VectorXd s = exact_stress(time_), v = exact_velocity(time_);
    summary.stress_errors = relative_errors(stress(), s, vol, z * v);
    summary.velocity_errors = relative_errors(velocity(), v, vol, s / z);
  }
  summary.wall_seconds = std::chrono::duration<double>(clock::now() - start).count();
  if (writes) {
    history.close();
    summary.files.push_back(directory + "/energy.csv");
    const std::string path = directory + "/summary.json";
    summary.files.push_back(path);
    const nlohmann::json j = summary.to_json();
    output::write_atomically(path, [&](std::ostream& out) { out << j.dump(2) << '\n'; });
  }
  return summary;
}

}  // namespace dgmpm
