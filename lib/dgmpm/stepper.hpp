#pragma once
// One DGMPM step of a particle configuration: the discretisation, its operator (DCU or CTU
// fluxes) and one time integrator (Euler or RK2), built together from one set of options. The
// solver, the whole-scene stability check and the von Neumann analysis all step through it, so
// that what is analysed is what runs.

#include "dg_operator.hpp"
#include "discretisation.hpp"
#include "time_integration.hpp"

#include <optional>
#include <variant>

namespace dgmpm {

struct StepperOptions {
  TimeScheme time = TimeScheme::euler;
  FluxScheme flux = FluxScheme::dcu;
  Formulation formulation = Formulation::consistent;
  // Cells of one layout share its values (Discretisation::set_layout_sharing); off only to check
  // that the results do not depend on it.
  bool share_layouts = true;
};

// The physics' own particle step over dt for `particles` (a constitutive correction of each
// state and its internal variables, as `particle_step(p, q)` of DGOperator's stages), or none.
template <class Physics>
auto physics_particle_step(ParticlesOf<Physics>& particles,
                           const std::vector<typename Physics::Material>& materials, double dt) {
  if constexpr (physics::ParticleStepPhysics<Physics>) {
    return [&particles, &materials, dt](int p, auto&& q) {
      Physics::particle_step(q, particles.internal.col(p), materials[particles.material[p]], dt);
    };
  } else {
    return NoParticleStep{};
  }
}

template <physics::DGPhysics Physics>
requires physics::InternalVariablesStepped<Physics>
class Stepper {
 public:
  static constexpr int dim = Physics::dim;
  using Op = DGOperator<Physics>;
  using Disc = Discretisation<Physics>;
  using ParticleSet = ParticlesOf<Physics>;

  // grid and boundaries are referenced and must outlive the stepper. Only the chosen
  // integrator's buffers exist.
  Stepper(const Grid<dim>& grid, const Boundaries<dim>& boundaries, const StepperOptions& options)
      : grid_(grid), boundaries_(boundaries), options_(options) {
    disc_.set_formulation(options.formulation);
    disc_.set_layout_sharing(options.share_layouts);
    switch (options.time) {
      case TimeScheme::euler:
        integrator_.template emplace<ForwardEuler<Physics>>();
        break;
      case TimeScheme::rk2:
        integrator_.template emplace<HeunRK2<Physics>>();
        break;
    }
  }
  Stepper(const Stepper&) = delete;  // the operator refers to the members
  Stepper& operator=(const Stepper&) = delete;

  // Rebuilds the discretisation (and the operator on first use) from the particles' positions.
  // Throws ParticleOutsideGrid.
  void rebuild(const ParticleSet& particles,
               const std::vector<typename Physics::Material>& materials) {
    disc_.build(grid_, particles, materials);
    if (!op_) op_.emplace(grid_, disc_, boundaries_, options_.flux);
  }

  // Returns whether every new particle state is finite (checked as the stage writes them).
  // `particle_step(p, q)` runs at each particle once its new state q is interpolated, in the same
  // sweep (DGOperator's NoParticleStep: none).
  template <class ParticleStep = NoParticleStep>
  bool step(typename Op::ParticleField& q, const Eigen::VectorXd& mass, double t, double dt,
            const ParticleStep& particle_step = {}) {
    return std::visit(
        [&](auto& integrator) { return integrator.step(*op_, q, mass, t, dt, particle_step); },
        integrator_);
  }

  // A step of `particles`, with the physics' own particle step (physics_particle_step).
  bool step(ParticleSet& particles, const std::vector<typename Physics::Material>& materials,
            double t, double dt) {
    return step(particles.state, particles.mass, t, dt,
                physics_particle_step<Physics>(particles, materials, dt));
  }

  const StepperOptions& options() const { return options_; }
  const Disc& discretisation() const { return disc_; }
  const Op& op() const { return *op_; }

 private:
  const Grid<dim>& grid_;
  const Boundaries<dim>& boundaries_;
  StepperOptions options_;
  Disc disc_;
  std::optional<Op> op_;
  std::variant<ForwardEuler<Physics>, HeunRK2<Physics>> integrator_;
};

}  // namespace dgmpm
