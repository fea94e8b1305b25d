#pragma once
// The readable definition of a DGMPM step: the specification the fused sweeps of DGOperator are
// tested against, to the last bit (tests/solver_fused_steps.cpp). Four stages, each over whole
// arrays, composed from the operator's per-cell and per-face parts (each defined once, in
// DGOperator): project (particles to nodes), residual (volume terms cell by cell, then every
// face's flux scattered to its two cells' face nodes), update (q += dt M^-1 r), interpolate
// (nodes to particles, then the physics' per-particle step). Euler is one residual; Heun's RK2
// two, its second at the first stage damped at near-empty nodes (DGOperator::project_and_advance)
// with what damping took away added back at the end. Slow (nodal arrays written and read back at
// every stage, faces stored): for tests and for reading, not for runs.

#include "stepper.hpp"

#include <algorithm>
#include <array>
#include <vector>

namespace dgmpm {

template <physics::DGPhysics Physics>
requires physics::InternalVariablesStepped<Physics>
class ReferenceStepper {
 public:
  using Op = DGOperator<Physics>;
  using Disc = Discretisation<Physics>;
  using NodalField = typename Op::NodalField;
  using ParticleField = typename Op::ParticleField;
  using State = typename Physics::State;
  static constexpr int dim = Physics::dim, npc = Op::npc;

  // The same operator, discretisation and schemes as `stepper` (which must outlive this).
  explicit ReferenceStepper(const Stepper<Physics>& stepper)
      : op_(stepper.op()), disc_(stepper.discretisation()), options_(stepper.options()) {}

  // One step of the particle states qp, as Stepper::step; `particle_step(p, q)` at each particle
  // once its new state is interpolated. Returns whether every new state is finite.
  template <class ParticleStep = NoParticleStep>
  bool step(ParticleField& qp, const Eigen::VectorXd& mass, double t, double dt,
            const ParticleStep& particle_step = {}) const {
    NodalField q0, r;
    project(qp, mass, q0);
    residual(q0, mass, t, dt, r);
    switch (options_.time) {
      case TimeScheme::euler:
        update(q0, r, dt);
        interpolate(q0, qp, particle_step);
        break;
      case TimeScheme::rk2: {
        NodalField q1 = q0, excess = NodalField::Zero(Physics::n_comp, op_.num_nodes());
        update(q1, r, dt);
        damp_near_empty(q0, q1, excess);  // q1: the damped first stage
        NodalField q2 = q1;
        residual(q1, mass, t + dt, dt, r);
        update(q2, r, dt);
        NodalField q = 0.5 * (q0 + q2);
        for (int c = 0; c < disc_.num_cells(); ++c)
          if (disc_.has_near_empty_nodes() && disc_.occupied(c) && disc_.near_empty(c))
            q.template middleCols<npc>(c * npc) += 0.5 * excess.template middleCols<npc>(c * npc);
        interpolate(q, qp, particle_step);
        break;
      }
    }
    return qp.allFinite();
  }

  // A step of `particles`, with the physics' own particle step, as Stepper's.
  bool step(ParticlesOf<Physics>& particles,
            const std::vector<typename Physics::Material>& materials, double t, double dt) const {
    return step(particles.state, particles.mass, t, dt,
                physics_particle_step<Physics>(particles, materials, dt));
  }

  // q = M^-1 sum_p m_p q_p S_p^T cell by cell; a massless node copies the node standing in for it.
  void project(const ParticleField& qp, const Eigen::VectorXd& mass, NodalField& q) const {
    q.setZero(Physics::n_comp, op_.num_nodes());
    for (int c = 0; c < disc_.num_cells(); ++c)
      for (int e = disc_.cell_begin(c); e < disc_.cell_end(c); ++e) {
        const int p = disc_.entry_particle(e);
        q.template middleCols<npc>(c * npc) +=
            (mass[p] * qp.col(p)) * disc_.entry_shape(e).transpose();
      }
    for (int i = 0; i < op_.num_nodes(); ++i)
      if (disc_.node_source(i) == i) q.col(i) *= disc_.inverse_mass(i);
    copy_massless(q);
  }

  // r = volume terms of the occupied cells, then each face's flux F_l(q*) (CTU: q* corrected by
  // the transverse waves of the fluctuations entering the faces' cells) times the face weight,
  // taken from the minus cell's upper nodes and given to the plus cell's lower nodes.
  void residual(const NodalField& q, const Eigen::VectorXd& mass, double t, double dt,
                NodalField& r) const {
    r.setZero(Physics::n_comp, op_.num_nodes());
    for (int c = 0; c < disc_.num_cells(); ++c) {
      if (!disc_.occupied(c)) continue;
      typename Op::CellBlock rc = Op::CellBlock::Zero();
      op_.add_volume_term(c, q.template middleCols<npc>(c * npc), mass, rc);
      r.template middleCols<npc>(c * npc) = rc;
    }
    std::array<NodalField, dim> star;
    typename Op::FaceFluctuations w;
    std::array<std::vector<char>, dim> active;
    for (int l = 0; l < dim; ++l) {
      star[l].setZero(Physics::n_comp, op_.num_faces(l));
      w[l].setZero(Physics::n_comp, 2 * op_.num_faces(l));
      active[l].assign(op_.num_faces(l), 0);
      for (int f = 0; f < op_.num_faces(l); ++f) {
        State s = State::Zero();
        active[l][f] = op_.face_star(l, f, q, t, s);
        star[l].col(f) = s;
        if constexpr (Op::corner_transport) {
          const auto [cm, cp] = op_.face_cells(l, f);
          for (int side = 0; side < 2; ++side) {
            const int c = side ? cp : cm;
            if (options_.flux == FluxScheme::ctu && c >= 0 && disc_.occupied(c))
              w[l].col(2 * f + side) = op_.entering_fluctuation(l, f, s, q, dt, side);
          }
        }
      }
    }
    for (int l = 0; l < dim; ++l)
      for (int f = 0; f < op_.num_faces(l); ++f) {
        if (!active[l][f]) continue;
        State s = star[l].col(f);
        if constexpr (Op::corner_transport)
          if (options_.flux == FluxScheme::ctu) s += op_.transverse_correction(l, f, w, q);
        const auto [cm, cp] = op_.face_cells(l, f);
        for (int side = 0; side < 2; ++side) {
          const int c = side ? cp : cm;
          if (c < 0 || !disc_.occupied(c)) continue;
          const State fl = op_.face_weight(l) * Physics::flux(l, s, disc_.cell_material(c));
          for (int a = 0; a < npc; ++a)
            if (((a >> l) & 1) == !side) r.col(c * npc + a) += side ? fl : State(-fl);
        }
      }
  }

  // q += dt M^-1 r, a massless node's residual moved to the node standing in for it, whose new
  // value it then copies.
  void update(NodalField& q, NodalField r, double dt) const {
    for (int i = 0; i < op_.num_nodes(); ++i) {
      const int s = disc_.node_source(i);
      if (s >= 0 && s != i) r.col(s) += r.col(i);
    }
    for (int i = 0; i < op_.num_nodes(); ++i)
      if (disc_.node_source(i) >= 0) q.col(i) += (dt * disc_.inverse_mass(i)) * r.col(i);
    copy_massless(q);
  }

  // Each particle's state from its cell's nodes, then its particle step.
  template <class ParticleStep = NoParticleStep>
  void interpolate(const NodalField& q, ParticleField& qp,
                   const ParticleStep& particle_step = {}) const {
    for (int c = 0; c < disc_.num_cells(); ++c)
      for (int e = disc_.cell_begin(c); e < disc_.cell_end(c); ++e) {
        const int p = disc_.entry_particle(e);
        qp.col(p) = q.template middleCols<npc>(c * npc) * disc_.entry_shape(e);
        if constexpr (!std::is_same_v<ParticleStep, NoParticleStep>) particle_step(p, qp.col(p));
      }
  }

 private:
  // RK2's first stage at near-empty nodes (a node with mass under stage_share of its cell's):
  // q1 becomes q0 + w (q1 - q0), w = share / stage_share, and `excess` the rest, (1 - w) (q1 -
  // q0), written as the difference taken away. Massless nodes keep their copy.
  void damp_near_empty(const NodalField& q0, NodalField& q1, NodalField& excess) const {
    if (!disc_.has_near_empty_nodes()) return;
    for (int c = 0; c < disc_.num_cells(); ++c) {
      if (!disc_.occupied(c) || !disc_.near_empty(c)) continue;
      for (int a = 0; a < npc; ++a) {
        const int i = c * npc + a;
        const double share = disc_.node_mass(i) / disc_.cell_mass(c);
        const double w =
            disc_.source_corner(i) == a ? std::min(1.0, share / Disc::stage_share) : 1.0;
        excess.col(i) = (1.0 - w) * (q1.col(i) - q0.col(i));
        q1.col(i) -= excess.col(i);
      }
    }
  }

  void copy_massless(NodalField& q) const {
    for (int i = 0; i < op_.num_nodes(); ++i) {
      const int s = disc_.node_source(i);
      if (s >= 0 && s != i) q.col(i) = q.col(s);
    }
  }

  const Op& op_;
  const Disc& disc_;
  StepperOptions options_;
};

}  // namespace dgmpm
