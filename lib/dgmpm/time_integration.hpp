#pragma once
// Explicit integrators on the nodal values (docs/method.md, "Time integration"). Each owns only
// the buffers it needs. RK2 is Heun's method; the intermediate stage stays on the grid.

#include "dg_operator.hpp"

namespace dgmpm {

enum class TimeScheme { euler, rk2 };

inline const char* to_string(TimeScheme s) {
  return s == TimeScheme::euler ? "euler" : "rk2";
}

template <class Physics>
class ForwardEuler {
 public:
  using Op = DGOperator<Physics>;
  static constexpr const char* name = "euler";

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
  static constexpr const char* name = "rk2";

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
