#pragma once
// The spectral radius of a DGMPM configuration's one-step operator, frozen as it is (particles,
// boundaries with their data set to zero): what `courant --scene` searches over C, and what a
// run's scene guard (time.check_scene_every) evaluates at its own time step.

#include <dgmpm/boundary.hpp>
#include <dgmpm/grid.hpp>
#include <dgmpm/particles.hpp>
#include <dgmpm/stepper.hpp>
#include <stability/arpack_spectrum.hpp>
#include <stability/step_operator.hpp>

#include <vector>

namespace dgmpm {

// The boundaries' linear part: a traction side acts as a free one, a velocity side as a fixed
// one; both reflect, as void cells do, so the operator is normal enough for its spectrum to speak.
template <int Dim>
Boundaries<Dim> homogeneous(const Boundaries<Dim>& b) {
  Boundaries<Dim> h = b;
  for (auto& axis : h)
    for (auto& side : axis)
      for (auto& s : side.segments) {
        if (s.condition.kind == BoundaryKind::traction) s.condition.kind = BoundaryKind::free;
        if (s.condition.kind == BoundaryKind::velocity) s.condition.kind = BoundaryKind::fixed;
        s.condition.value = {};
      }
  return h;
}

// rho of the particle map of one step dt of lib's stepper on these particles (ARPACK; dense
// when small).
template <class Physics>
double frozen_spectral_radius(const Grid<Physics::dim>& grid,
                              const Boundaries<Physics::dim>& boundaries,
                              const ParticlesOf<Physics>& particles,
                              const std::vector<typename Physics::Material>& materials,
                              const StepperOptions& options, double dt) {
  const Boundaries<Physics::dim> bc = homogeneous<Physics::dim>(boundaries);
  Stepper<Physics> stepper(grid, bc, options);
  stepper.rebuild(particles, materials);
  const int n = Physics::n_comp * particles.size();
  stability::ArpackOptions arpack;
  if (n > 2000) {  // as courant --scene: ten steps per product, rho to about 1e-7
    arpack.steps_per_product = 10;
    arpack.basis_size = 60;
    arpack.tolerance = 1e-6;
  }
  return stability::spectral_radius(n, stability::step_operator(stepper, particles.mass, dt),
                                    arpack);
}

}  // namespace dgmpm
