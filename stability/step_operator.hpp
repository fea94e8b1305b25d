#pragma once
// One step of lib's integrator seen as a linear operator on the particle state, for ARPACK
// (arpack_spectrum.hpp): the whole-scene analysis (docs/method.md, "Stability") with the solver's
// own step.

#include "stability/arpack_spectrum.hpp"

#include <dgmpm/stepper.hpp>

#include <Eigen/Core>

namespace dgmpm::stability {

// x and y hold Physics::n_comp values per particle, particle after particle (the storage order
// of Particles::state). The step is linear only with homogeneous boundary data (zero prescribed
// traction or velocity): give the stepper such boundaries. stepper and mass are referenced, not
// copied, and must outlive the returned operator.
template <class Physics>
LinearOperator step_operator(Stepper<Physics>& stepper, const Eigen::VectorXd& mass, double dt) {
  using Field = typename DGOperator<Physics>::ParticleField;
  return [&stepper, &mass, dt, state = Field()](const double* x, double* y) mutable {
    const auto n = mass.size();
    state = Eigen::Map<const Field>(x, Physics::n_comp, n);
    stepper.step(state, mass, 0.0, dt);
    Eigen::Map<Field>(y, Physics::n_comp, n) = state;
  };
}

}  // namespace dgmpm::stability
