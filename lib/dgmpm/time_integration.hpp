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

  void step(const Op& op, typename Op::ParticleField& qp, const Eigen::VectorXd& mass, double t,
            double dt) {
    op.project(qp, mass, q_);
    op.advance_to_particles(q_, t, dt, qp);
  }

 private:
  typename Op::NodalField q_;
};

template <class Physics>
class HeunRK2 {
 public:
  using Op = DGOperator<Physics>;
  static constexpr const char* name = "rk2";

  // q1 = q0 + dt L(q0, t); q^{n+1} = (q0 + q1 + dt L(q1, t + dt)) / 2.
  void step(const Op& op, typename Op::ParticleField& qp, const Eigen::VectorXd& mass, double t,
            double dt) {
    op.project(qp, mass, q0_);
    op.advance(q0_, t, dt, q1_);
    op.average_to_particles(q0_, q1_, t + dt, dt, qp);
  }

 private:
  typename Op::NodalField q0_, q1_;
};

}  // namespace dgmpm
