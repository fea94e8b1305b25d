#pragma once
// The definitions of DgmpmMethod and MpmMethod (stepping_method.hpp), instantiated with
// Simulation (simulation_impl.hpp).

#include "solver/checkpoint.hpp"
#include "solver/simulation.hpp"
#include "solver/stepping_method.hpp"

#include <sstream>

namespace dgmpm {

namespace method_detail {

template <int Dim>
bool has_loads(const Grid<Dim>& grid, const Boundaries<Dim>& boundaries) {
  for (int a = 0; a < Dim; ++a)
    for (int side = 0; side < 2 && !grid.periodic[a]; ++side)
      for (const auto& s : boundaries[a][side].segments)
        if (s.condition.kind == BoundaryKind::traction ||
            s.condition.kind == BoundaryKind::velocity)
          return true;
  return false;
}

inline MpmVariant mpm_variant(scene::Method m) {
  switch (m) {
    case scene::Method::mpm_usf:
      return MpmVariant::usf;
    case scene::Method::mpm_musl:
      return MpmVariant::musl;
    case scene::Method::mpm_usl:
    case scene::Method::dgmpm:
      break;
  }
  return MpmVariant::usl;
}

inline double from_key(const nlohmann::json& h, const char* key) {
  return checkpoint::from_bits(h.at(key).get<std::uint64_t>());
}

}  // namespace method_detail

template <class Physics>
DgmpmMethod<Physics>::DgmpmMethod(const RunParts<Physics>& run) : run_(run) {
  const scene::Scene& scene = run_.scene;
  auto& problem = run_.problem;
  auto& warnings = run_.warnings;
  stepper_ =
      std::make_unique<Stepper<Physics>>(problem.grid, problem.boundaries, stepper_options(scene));
  stepper_->rebuild(problem.particles, problem.materials);
  time_control_.emplace(scene, run_.max_speed);
  dt_ = time_control_->time_step(problem.grid, stepper_->discretisation(), problem.particles,
                                 problem.materials);
  if (!time_control_->automatic()) warn_if_above_admissible();
  if (dim > 1 && time_control_->automatic() && scene.particles_move) {
    const int cell =
        time_control_->first_cell_past_the_lattice(stepper_->discretisation(), problem.particles);
    if (cell >= 0)
      warnings.push_back(
          "\"courant\": \"auto\" with moving particles: cell " + std::to_string(cell) +
          " holds a layout no lattice bounds (under the consistent formulation: one or two "
          "particles per cell, or any number placed as a product of per-axis positions): such "
          "layouts are analysed anew as their particles drift, 0.05-0.5 s each and several per "
          "step, and choosing steps may take most of the run; a fixed Courant number below "
          "`dgmpm courant`'s limit for the layout, with time.check_scene_every as a guard, is "
          "far cheaper");
  }
  if (scene.time.check_scene_every > 0) check_scene(0, 0.0);
  if (scene.formulation == Formulation::paper) warn_if_overfull_cell(0, 0.0);
  if (dim > 1 && scene.flux == FluxScheme::ctu && scene.time.integrator == TimeScheme::rk2)
    warnings.push_back(
        "flux \"ctu\" with integrator \"rk2\": CTU's transverse corrections are a one-step "
        "(Euler) device and RK2 already holds the cross terms they add; the pair is stable only "
        "below Courant 1 even with one particle per cell (about 0.75 for nu = 0.3) and is not "
        "exact at Courant 1 (use \"dcu\" with \"rk2\" or \"ctu\" with \"euler\")");
  loaded_ = method_detail::has_loads<dim>(problem.grid, problem.boundaries);
  if (loaded_) power_ = load_power(0.0);
}

// The whole scene's operator, frozen, at the chosen step: halved until its spectral radius is at
// most 1 (to the eigensolver's accuracy), the factor kept until the next check. What the
// per-layout analysis cannot see (a configuration no cell's periodic model holds) is caught here.
template <class Physics>
void DgmpmMethod<Physics>::check_scene(long step, double t) {
  constexpr double kTolerance = 1e-6;  // ARPACK's rho: to about 1e-8 (1e-7 on large scenes)
  constexpr int kHalvings = 40;
  const auto& problem = run_.problem;
  const double h = problem.grid.cell_size.minCoeff();
  double factor = 1.0, first = 0.0, rho = 0.0;
  for (int k = 0; k <= kHalvings; ++k) {
    rho = frozen_spectral_radius<Physics>(problem.grid, problem.boundaries, problem.particles,
                                          problem.materials, stepper_options(run_.scene),
                                          factor * dt_);
    if (k == 0) first = rho;
    if (rho <= 1 + kTolerance) break;
    factor *= 0.5;
  }
  scene_guard_factor_ = factor;
  if (factor == 1.0) return;
  dt_ *= factor;
  if (scene_guard_warned_) return;
  scene_guard_warned_ = true;
  const double max_speed = run_.max_speed;
  std::ostringstream s;
  s << format_step(step, t) << ": the whole scene's operator has spectral radius " << first
    << " at the automatic step (C = " << dt_ / factor * max_speed / h << "); the step is scaled by "
    << factor << " (C = " << dt_ * max_speed / h << ", spectral radius " << rho
    << ") until the next check (time.check_scene_every; warned once)";
  run_.warnings.push_back(s.str());
}

template <class Physics>
void DgmpmMethod<Physics>::warn_if_above_admissible() {
  // A 2D layout takes 0.1-3 s to analyse: a scene of many distinct layouts is not checked, and
  // says so.
  constexpr int kMaxLayouts2D = 16;
  const scene::Scene& scene = run_.scene;
  const auto& particles = run_.problem.particles;
  const auto& disc = stepper_->discretisation();
  if (dim > 1) {
    const int layouts = time_control_->layouts_to_analyse(disc, particles);
    if (layouts > kMaxLayouts2D) {
      run_.warnings.push_back(
          "Courant number " + std::to_string(scene.time.courant) +
          " not checked against the admissible one: " + std::to_string(layouts) +
          " distinct cell layouts (more than " + std::to_string(kMaxLayouts2D) +
          " take long to analyse in 2D); \"courant\": \"auto\" analyses them "
          "as the run needs them, `dgmpm courant --scene` analyses the whole scene");
      return;
    }
  }
  const auto limit = time_control_->smallest_admissible(disc, particles);
  if constexpr (state_dependent_speed) {
    const double safe = kFiniteStrainSafety * limit.courant;
    if (scene.time.courant > safe * (1 + 1e-9) && scene.time.courant <= limit.courant) {
      std::ostringstream s;
      s << "Courant number " << scene.time.courant << " is above " << kFiniteStrainSafety
        << " times the admissible " << std::setprecision(6) << limit.courant
        << ": with finite strain a step chosen with the speeds at its start can gain energy at "
           "shocks (the state behind moves faster), and the energy may exceed the initial energy "
           "plus the loads' work (\"auto\" uses "
        << safe << ")";
      run_.warnings.push_back(s.str());
    }
  }
  if (!(scene.time.courant > limit.courant * (1 + 1e-9))) return;
  std::ostringstream s;
  s << "Courant number " << scene.time.courant << " is above the admissible "
    << std::setprecision(6) << limit.courant << " (" << scene::to_string(scene.time.criterion)
    << ", " << scene::to_string(scene.time.integrator);
  if (dim > 1) s << ", " << to_string(scene.flux);
  s << ") of the layout of cell " << limit.cell << " (positions "
    << stability::describe_positions(limit.layout) << ", masses "
    << stability::describe(limit.layout.masses);
  if (limit.fill < 1 - 1e-9) s << ", fill " << limit.fill;
  s << "): the run may be unstable";
  run_.warnings.push_back(s.str());
}

// With the paper's pseudo-stiffness, a cell whose particles carry more than rho times its volume
// (moving particles piling up) breaks the scheme's consistency: the volume term scales with the
// cell's mass, the face fluxes do not, so a constant state changes at a rate (fill - 1) F / (rho h)
// there, however small dt is. No time step restores monotonicity then; the run says so once,
// naming where it began (the consistent pseudo-stiffness, the default, removes the cause).
template <class Physics>
void DgmpmMethod<Physics>::warn_if_overfull_cell(long step, double t) {
  // The rebuild found the first over-full cell (no pass over the cells here); over ranks, the
  // first of theirs by the grid's numbering (every rank says the same).
  const auto& halo = run_.halo;
  const auto& disc = stepper_->discretisation();
  int c = disc.first_overfull_cell();
  if (halo && c >= 0) {
    // A window's numbering wraps across periodic sides: the rank's first owned over-full cell by
    // the grid's numbering (a pass over the window, only once it has one).
    c = -1;
    for (int k = 0; k < disc.num_cells(); ++k)
      if (halo->owns_cell(k) && disc.occupied(k) && disc.overfull(k) &&
          (c < 0 || full_cell(k) < full_cell(c)))
        c = k;
  }
  double cell = c >= 0 ? full_cell(c) : -1, fill = c >= 0 ? disc.fill(c) : 0;
  if (halo) {
    constexpr double none = std::numeric_limits<double>::infinity();
    const double mine = c >= 0 ? cell : none, first = halo->comm().min(mine);
    fill = halo->comm().min(mine == first ? fill : none);
    cell = first == none ? -1 : first;
  }
  if (cell < 0) return;
  std::ostringstream s;
  s << format_step(step, t) << ": cell " << static_cast<long>(cell) << " holds "
    << std::setprecision(6) << fill
    << " times a full cell's mass; the operators do not preserve constant states in an "
       "over-full cell, so new extrema can appear whatever the time step (\"formulation\": "
       "\"consistent\" restores them)";
  run_.warnings.push_back(s.str());
  overfull_warned_ = true;
}

// Power of the boundary loads at time t on the current particle state.
template <class Physics>
double DgmpmMethod<Physics>::load_power(double t) const {
  const auto& p = run_.problem.particles;
  const auto& halo = run_.halo;
  if (!halo) return stepper_->op().boundary_power(p.state, p.mass, t);
  double power =
      stepper_->op().boundary_power(p.state, p.mass, t, [&](int c) { return halo->owns_cell(c); });
  halo->comm().sum({&power, 1});
  return power;
}

// The step for the particles' current layouts and states (check_scene's factor or check applied
// to an automatic one). A state past the hyperbolic range stops the run, naming its particle.
template <class Physics>
void DgmpmMethod<Physics>::choose_time_step(long step, double t) {
  auto& problem = run_.problem;
  const auto& halo = run_.halo;
  dt_ = time_control_->time_step(problem.grid, stepper_->discretisation(), problem.particles,
                                 problem.materials);
  if constexpr (state_dependent_speed) {
    check_hyperbolic(run_, owned(), std::isnan(dt_), step, t);
    run_.max_speed = time_control_->fastest_speed();
    if (halo) run_.max_speed = -halo->comm().min(-run_.max_speed);
  }
  if (halo) dt_ = halo->comm().min(dt_);  // every cell is some rank's: exact
  if (!time_control_->automatic()) return;
  const long every = run_.scene.time.check_scene_every;
  if (every > 0 && step % every == 0)
    check_scene(step, t);
  else
    dt_ *= scene_guard_factor_;
}

template <class Physics>
void DgmpmMethod<Physics>::summarise(RunSummary& summary) const {
  if (dim > 1) summary.run["flux"] = to_string(run_.scene.flux);
  summary.layouts_analysed = time_control_->layouts_analysed();
  summary.time_step_seconds = time_control_->selection_seconds();
  summary.layout_analysis_seconds = time_control_->analysis_seconds();
}

template <class Physics>
void DgmpmMethod<Physics>::save(nlohmann::json& header) const {
  using checkpoint::bits;
  header["dt"] = bits(dt_);
  header["work"] = bits(work_);
  header["power"] = bits(power_);
  header["overfull_warned"] = overfull_warned_;
  header["scene_guard_factor"] = bits(scene_guard_factor_);
  header["scene_guard_warned"] = scene_guard_warned_;
}

template <class Physics>
void DgmpmMethod<Physics>::restore(const nlohmann::json& h) {
  dt_ = method_detail::from_key(h, "dt");
  work_ = method_detail::from_key(h, "work");
  power_ = method_detail::from_key(h, "power");
  overfull_warned_ = h.at("overfull_warned").get<bool>();
  scene_guard_factor_ = method_detail::from_key(h, "scene_guard_factor");
  scene_guard_warned_ = h.at("scene_guard_warned").get<bool>();
  stepper_->rebuild(run_.problem.particles, run_.problem.materials);
}

template <class Physics>
MpmMethod<Physics>::MpmMethod(const RunParts<Physics>& run)
    : run_(run), mpm_(run.problem.grid, run.problem.boundaries, run.problem.materials,
                      method_detail::mpm_variant(run.scene.method), run.scene.update) {
  const scene::Scene& scene = run_.scene;
  if (scene.time.courant_auto)
    throw scene::SceneError(scene.source +
                            ": time.courant: value \"auto\" is not available for method \"" +
                            scene::to_string(scene.method) +
                            "\"; allowed: a positive number (the stability analysis is DGMPM's)");
  dt_ = scene.time.courant * run_.problem.grid.cell_size.minCoeff() / run_.problem.max_wave_speed();
}

template <class Physics>
void MpmMethod<Physics>::save(nlohmann::json& header) const {
  using checkpoint::bits;
  header["dt"] = bits(dt_);
  header["mpm_load_work"] = bits(mpm_.load_work());
}

template <class Physics>
void MpmMethod<Physics>::restore(const nlohmann::json& h) {
  dt_ = method_detail::from_key(h, "dt");
  mpm_.set_load_work(method_detail::from_key(h, "mpm_load_work"));
  mpm_.relocate();  // the particles are the checkpoint's
}

}  // namespace dgmpm
