#pragma once
// Explicit integrators on the nodal values (docs/method.md, "Time integration"). Each owns only
// the buffers it needs. RK2 is Heun's method; the intermediate stage stays on the grid.

#include "dg_operator.hpp"

#include <array>

namespace dgmpm {

enum class TimeScheme { euler, rk2 };
// Every scheme, in the order names are listed to users.
inline constexpr std::array<TimeScheme, 2> time_schemes{TimeScheme::euler, TimeScheme::rk2};

// What the rest of the code derives from a scheme: its name (scenes, CLI, outputs) and its
// number of stages, that is the operator evaluations per step: the one-step map's degree in dt
// (stability/), and the ghost layers of cells a distributed step needs (one per stage). The
// stages themselves are the fused sweeps of ForwardEuler and HeunRK2 below. No default branch:
// a new scheme is a -Wswitch warning here (and in Stepper) until it is described.
struct TimeSchemeTraits {
  const char* name;
  int stages;
};

constexpr TimeSchemeTraits traits(TimeScheme s) {
  switch (s) {
    case TimeScheme::euler:
      return {"euler", 1};
    case TimeScheme::rk2:
      return {"rk2", 2};
  }
  return {"", 0};  // not a TimeScheme value
}

inline const char* to_string(TimeScheme s) {
  return traits(s).name;
}

template <class Physics>
class ForwardEuler {
 public:
  using Op = DGOperator<Physics>;

  // Returns whether every new particle state is finite. `particle_step`: DGOperator's.
  template <class ParticleStep = NoParticleStep>
  bool step(const Op& op, typename Op::ParticleField& qp, const Eigen::VectorXd& mass, double t,
            double dt, const ParticleStep& particle_step = {}) {
    return op.project_and_advance_to_particles(qp, mass, t, dt, q_, particle_step);
  }

 private:
  typename Op::NodalField q_;
};

template <class Physics>
class HeunRK2 {
 public:
  using Op = DGOperator<Physics>;

  // q1 = q0 + dt L(q0, t); q^{n+1} = (q0 + q1 + dt L(q1, t + dt)) / 2 (L evaluated at a damped
  // q1 at near-empty nodes: DGOperator::project_and_advance).
  // The particle step follows the second stage only: the first stays on the grid.
  template <class ParticleStep = NoParticleStep>
  bool step(const Op& op, typename Op::ParticleField& qp, const Eigen::VectorXd& mass, double t,
            double dt, const ParticleStep& particle_step = {}) {
    op.project_and_advance(qp, mass, t, dt, q0_, q1_, excess_);
    return op.average_to_particles(q0_, q1_, excess_, mass, t + dt, dt, qp, particle_step);
  }

 private:
  typename Op::NodalField q0_, q1_, excess_;  // excess_: only when some node is near-empty
};

}  // namespace dgmpm
