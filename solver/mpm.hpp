#pragma once
// Classical MPM baseline (Sulsky, Zhou, Schreyer 1995) on the same grid, particles
// and boundaries as DGMPM: shared (continuous) nodes, multilinear shape functions, lumped mass,
// USL / USF / MUSL orderings with a FLIP or PIC particle velocity update.
// Everything is dimension-generic; the physics supplies the constitutive part: the stress tensor
// of a particle state and the stress rate of a velocity gradient (the velocity is the state's
// last Dim components).

#include "solver/scene.hpp"

#include <dgmpm/boundary.hpp>
#include <dgmpm/discretisation.hpp>
#include <dgmpm/grid.hpp>
#include <dgmpm/particles.hpp>
#include <dgmpm/physics/contract.hpp>
#include <dgmpm/physics/elastic_bar.hpp>
#include <dgmpm/physics/plane_strain.hpp>
#include <dgmpm/shape_functions.hpp>
#include <dgmpm/thread_share.hpp>

#include <Eigen/Core>
#include <algorithm>
#include <array>
#include <sstream>
#include <utility>
#include <vector>

namespace dgmpm {

enum class MpmVariant { usl, usf, musl };
// The scene's own choice, FLIP or PIC.
using MpmVelocityUpdate = scene::MpmUpdate;

inline const char* to_string(MpmVariant v) {
  switch (v) {
    case MpmVariant::usl:
      return "usl";
    case MpmVariant::usf:
      return "usf";
    case MpmVariant::musl:
      return "musl";
  }
  return "?";
}

template <class Physics>
class Mpm {
  static_assert(physics::MpmConstitutive<Physics>, "the MPM baseline needs a constitutive model");

 public:
  static constexpr int Dim = Physics::dim;
  static constexpr int npc = 1 << Dim;  // nodes of a cell
  static constexpr int ncomp = Physics::n_comp;
  static constexpr int velocity_row = ncomp - Dim;
  // Runs of this many particles or more step on threads (below, a parallel region costs more
  // than it saves): the loops over particles and over nodes, and the transfers to the grid (mass,
  // momentum, internal force), scattered by colours of cell layers (scatter): results do not depend
  // on the number of threads. (A gather per node in a fixed order threads them too, but reads each
  // particle once per node: one core lost 26% on the 2D plate.)
  static constexpr int kThreadedParticles = 4096;
  using Material = typename Physics::Material;
  using Tensor = Eigen::Matrix<double, Dim, Dim>;
  using Vec = Eigen::Matrix<double, Dim, 1>;
  using ParticleSet = ParticlesOf<Physics>;
  using NodalVectors = Eigen::Matrix<double, Dim, Eigen::Dynamic>;

  Mpm(const Grid<Dim>& grid, const Boundaries<Dim>& bc, std::vector<Material> materials,
      MpmVariant variant, MpmVelocityUpdate update)
      : grid_(grid), bc_(bc), materials_(std::move(materials)), variant_(variant), update_(update) {
    num_nodes_ = 1;
    for (int l = 0; l < Dim; ++l) {
      nodes_[l] = grid_.cells[l] + (grid_.periodic[l] ? 0 : 1);
      stride_[l] = num_nodes_;
      num_nodes_ *= nodes_[l];
    }
  }

  const Grid<Dim>& grid() const { return grid_; }
  int num_nodes() const { return num_nodes_; }

  // Node `a` (bit l: side along axis l) of the cell with multi-index k; periodic axes wrap.
  int node(const typename Grid<Dim>::Index& k, int a) const {
    int i = 0;
    for (int l = 0; l < Dim; ++l) {
      int kl = k[l] + ((a >> l) & 1);
      if (kl == nodes_[l]) kl = 0;  // only reachable on a periodic axis
      i += kl * stride_[l];
    }
    return i;
  }

  // Nodal fields of the last step, for diagnostics and tests: lumped mass, velocity at t^n and
  // at t^{n+1} (after boundary conditions).
  const Eigen::VectorXd& node_mass() const { return mass_; }
  const NodalVectors& node_velocity_old() const { return vel_old_; }
  const NodalVectors& node_velocity_new() const { return vel_new_; }

  // One step from t to t + dt. Allocation-free once the particle count is reached. Throws
  // ParticleOutsideGrid for a particle outside the grid, before any change at the start of the
  // step, or after the move that took it out.
  // The transfers are fused: one scatter to the grid of mass, momentum and (USL, MUSL) internal
  // force, one pass back to the particles of velocity, stress (USL, USF) and position.
  void step(ParticleSet& particles, double t, double dt, bool move_particles) {
    const bool usf = variant_ == MpmVariant::usf, musl = variant_ == MpmVariant::musl;
    locate(particles);
    force_.setZero(Dim, num_nodes_);
    project_mass_momentum(particles, vel_old_, !usf);
    apply_velocity_bc(vel_old_, t, &load_work_);
    if (usf) {  // the stress from v^n, then its force
      to_particles(particles, dt, {.stress_from = &vel_old_});
      scatter(particles.size(), [&](int p) { add_internal_force(particles, p); });
    }
    loaded_nodes_.clear();
    add_traction(t);
    vel_new_.resize(Dim, num_nodes_);
#pragma omp parallel for schedule(static) if (threaded(particles.size()))
    for (int i = 0; i < num_nodes_; ++i)
      vel_new_.col(i) =
          mass_[i] > 0.0 ? Vec(vel_old_.col(i) + (dt / mass_[i]) * force_.col(i)) : Vec::Zero();
    for (const auto& [i, f] : loaded_nodes_)
      load_work_ += 0.5 * dt * f.dot(vel_old_.col(i) + vel_new_.col(i));
    apply_velocity_bc(vel_new_, t + dt, &load_work_);
    if (!musl) {
      to_particles(particles, dt,
                   {.velocity = true,
                    .stress_from = usf ? nullptr : &vel_new_,
                    .move_with = move_particles ? &vel_new_ : nullptr});
      return;
    }
    // MUSL: the new particle velocities projected again, then stress and move from them.
    to_particles(particles, dt, {.velocity = true});
    project_mass_momentum(particles, vel_musl_, false);
    apply_velocity_bc(vel_musl_, t + dt);
    to_particles(particles, dt,
                 {.stress_from = &vel_musl_, .move_with = move_particles ? &vel_musl_ : nullptr});
  }

  // Energy the boundaries gave the body so far: work of the tractions on the nodal velocities
  // (trapezoidal over the step) and of the velocity constraints' reactions. An estimate for the
  // blow-up check, not an exact balance: MPM conserves no discrete energy.
  double load_work() const {
    return load_work_;
  }
  void set_load_work(double w) {
    load_work_ = w;
  }  // a restart's

 private:
  // --- constitutive part, from the physics ------------------------------------------------------
  static Vec particle_velocity(const ParticleSet& ps, int p) {
    return ps.state.col(p).template tail<Dim>();
  }
  static void set_particle_velocity(ParticleSet& ps, int p, const Vec& v) {
    ps.state.col(p).template tail<Dim>() = v;
  }
  // sigma += dt C : sym(grad v) at particle p, with grad v from the nodal velocities v, then the
  // physics' particle step (a constitutive correction) where it has one, as DGMPM's sweep does.
  void update_stress(ParticleSet& ps, int p, const NodalVectors& v, double dt) const {
    Tensor grad = Tensor::Zero();  // (i, j): dv_i / dx_j
    for (int a = 0; a < npc; ++a)
      grad.noalias() += v.col(node_(a, p)) * grad_.template block<Dim, 1>(a * Dim, p).transpose();
    auto q = ps.state.col(p);
    Physics::add_stress_rate(q, grad, materials_[ps.material[p]], dt);
    if constexpr (physics::ParticleStepPhysics<Physics>)
      Physics::particle_step(q, ps.internal.col(p), materials_[ps.material[p]], dt);
  }
  // f_i -= V_p sigma_p grad S_i(x_p) at the nodes of particle p.
  void add_internal_force(const ParticleSet& ps, int p) {
    const Tensor vs =
        ps.volume[p] * Physics::stress_tensor(ps.state.col(p), materials_[ps.material[p]]);
    for (int a = 0; a < npc; ++a)
      force_.col(node_(a, p)).noalias() -= vs * grad_.template block<Dim, 1>(a * Dim, p);
  }

  // --- generic part ------------------------------------------------------------------------------
  bool threaded(int np) const {
    return np >= kThreadedParticles;
  }

  // Calls add(p) for every particle p, on threads where there are many, each node receiving its
  // particles in the same order whatever their number. The layers of cells along the last axis
  // (rows) are grouped into kScatterBlocks blocks of consecutive rows, coloured even and odd (and
  // a periodic axis' last block alone when their count is odd: it shares nodes with block 0). Two
  // blocks of a colour share no node, so a colour's blocks are split between the threads; a node
  // receives a colour's particles from one block, in particle order.
  static constexpr int kScatterBlocks = 64;
  int scatter_blocks() const {
    return std::min(grid_.cells[Dim - 1], kScatterBlocks);
  }
  template <class Add>
  void scatter(int np, Add&& add) const {
    const int blocks = scatter_blocks();
    const bool wrap = grid_.periodic[Dim - 1] && blocks % 2 == 1 && blocks > 1;
    const auto colour = [&](int block) { return wrap && block == blocks - 1 ? 2 : block % 2; };
#pragma omp parallel if (threaded(np))
    {
      const Share mine = thread_share(blocks, team_place());
      for (int c = 0; c < (wrap ? 3 : 2); ++c) {
        for (int p = 0; p < np; ++p) {
          const int block = block_[p];
          if (block >= mine.begin && block < mine.end && colour(block) == c) add(p);
        }
#pragma omp barrier
      }
    }
  }

  // Nodes, shape values and gradients of every particle, and its cell's block (scatter).
  void locate(const ParticleSet& ps) {
    const int np = ps.size();
    node_.resize(npc, np);
    shape_.resize(npc, np);
    grad_.resize(npc * Dim, np);
    block_.resize(np);
    const long rows = grid_.cells[Dim - 1], blocks = scatter_blocks();
    const Vec inverse_h = grid_.cell_size.cwiseInverse();
    int outside = np;  // the first particle outside the grid
#pragma omp parallel for schedule(static) reduction(min : outside) if (threaded(np))
    for (int p = 0; p < np; ++p) {
      Vec xi;
      const int c = grid_.locate(ps.position.col(p), xi);
      if (c < 0) {
        outside = std::min(outside, p);
        continue;
      }
      const auto k = grid_.unflatten(c);
      block_[p] = static_cast<int>(k[Dim - 1] * blocks / rows);
      for (int a = 0; a < npc; ++a) node_(a, p) = node(k, a);
      shape_.col(p) = CellShape<Dim>::values(xi);
      const auto g = CellShape<Dim>::gradients(xi, inverse_h);
      for (int a = 0; a < npc; ++a) grad_.template block<Dim, 1>(a * Dim, p) = g.col(a);
    }
    if (outside < np) throw_outside_grid(ps, outside);
  }

  // Lumped mass and nodal velocity p_i / m_i (zero on massless nodes), and with `force` the
  // internal force, in one scatter.
  void project_mass_momentum(const ParticleSet& ps, NodalVectors& v, bool force) {
    mass_.setZero(num_nodes_);
    v.setZero(Dim, num_nodes_);
    const int np = ps.size();
    scatter(np, [&](int p) {
      const Vec vp = particle_velocity(ps, p);
      for (int a = 0; a < npc; ++a) {
        const int i = node_(a, p);
        const double w = shape_(a, p) * ps.mass[p];
        mass_[i] += w;
        v.col(i) += w * vp;
      }
      if (force) add_internal_force(ps, p);
    });
#pragma omp parallel for schedule(static) if (threaded(np))
    for (int i = 0; i < num_nodes_; ++i)
      if (mass_[i] > 0.0) v.col(i) /= mass_[i];
  }

  // What to_particles does at each particle, in this order: the velocity update (FLIP adds the
  // interpolated nodal velocity increment, PIC takes the interpolated velocity), the stress
  // update from the nodal velocities `stress_from`, the move with `move_with` (none when null).
  struct ToParticles {
    bool velocity = false;
    const NodalVectors* stress_from = nullptr;
    const NodalVectors* move_with = nullptr;
  };
  // One pass over the particles. Throws ParticleOutsideGrid for the first particle moved out.
  void to_particles(ParticleSet& ps, double dt, const ToParticles& what) const {
    const bool flip = update_ == MpmVelocityUpdate::flip;
    const int np = ps.size();
    int outside = np;  // the first particle outside the grid
#pragma omp parallel for schedule(static) reduction(min : outside) if (threaded(np))
    for (int p = 0; p < np; ++p) {
      if (what.velocity) {
        Vec v = Vec::Zero();
        for (int a = 0; a < npc; ++a) {
          const int i = node_(a, p);
          v +=
              shape_(a, p) * (flip ? Vec(vel_new_.col(i) - vel_old_.col(i)) : Vec(vel_new_.col(i)));
        }
        set_particle_velocity(ps, p, flip ? Vec(particle_velocity(ps, p) + v) : v);
      }
      if (what.stress_from) update_stress(ps, p, *what.stress_from, dt);
      if (what.move_with) {
        Vec vp = Vec::Zero();
        for (int a = 0; a < npc; ++a) vp += shape_(a, p) * what.move_with->col(node_(a, p));
        ps.position.col(p) += dt * vp;
        Vec xi;
        if (grid_.locate(ps.position.col(p), xi) < 0) outside = std::min(outside, p);
      }
    }
    if (outside < np) throw_outside_grid(ps, outside);
  }

  // Calls f(node, x, s) for the nodes of the grid face normal to `axis` on `side`, x being the
  // node's position and s the segment of its shape function's support on the face along the
  // tangential axes: [x - h, x + h] clipped to the face (the face is a point in 1D).
  template <class F>
  void for_each_face_node(int axis, int side, F&& f) const {
    int count = 1;
    for (int l = 0; l < Dim; ++l)
      if (l != axis) count *= nodes_[l];
    for (int n = 0; n < count; ++n) {
      int rest = n, i = (side ? nodes_[axis] - 1 : 0) * stride_[axis];
      Vec x, lo, hi;
      x[axis] = lo[axis] = hi[axis] = side ? grid_.upper(axis) : grid_.origin[axis];
      for (int l = 0; l < Dim; ++l) {
        if (l == axis) continue;
        const int kl = rest % nodes_[l];
        rest /= nodes_[l];
        i += kl * stride_[l];
        x[l] = grid_.origin[l] + kl * grid_.cell_size[l];
        lo[l] = grid_.periodic[l] ? x[l] - grid_.cell_size[l]
                                  : std::max(grid_.origin[l], x[l] - grid_.cell_size[l]);
        hi[l] = grid_.periodic[l] ? x[l] + grid_.cell_size[l]
                                  : std::min(grid_.upper(l), x[l] + grid_.cell_size[l]);
      }
      f(i, x, lo, hi);
    }
  }

  // Integral over [lo, hi] (tangential axes) of the node-at-x shape function restricted to the
  // segment s (1 in 1D).
  double face_weight(const Vec& x, const Vec& lo, const Vec& hi, const BoundarySegment<Dim>& s,
                     int axis) const {
    double w = 1.0;
    for (int l = 0; l < Dim; ++l) {
      if (l == axis) continue;
      const double a = std::max(lo[l], s.lo[l]), b = std::min(hi[l], s.hi[l]);
      if (!(a < b)) return 0.0;
      // Integral of the hat 1 - |y - x| / h over [a, b], split at its peak.
      const double h = grid_.cell_size[l];
      const auto primitive = [&](double y) {  // of the hat, from x
        const double d = y - x[l];
        return d - std::copysign(0.5 * d * d / h, d);
      };
      w *= primitive(b) - primitive(a);
    }
    return w;
  }

  // Fixed and velocity faces: the nodal velocity is the prescribed one; roller faces: its normal
  // component is zero. Imposed on v^n and on v^{n+1}, so the nodal acceleration there is that of
  // the prescription (zero when fixed).
  // Also adds to `injected` the kinetic energy the constraint gives the grid, 1/2 m (|v_bc|^2 -
  // |v|^2) per constrained node (the work of its reaction).
  void apply_velocity_bc(NodalVectors& v, double t, double* injected = nullptr) const {
    for (int l = 0; l < Dim; ++l) {
      if (grid_.periodic[l]) continue;
      for (int side = 0; side < 2; ++side) {
        const auto& bs = bc_[l][side];
        if (bs.segments.empty()) continue;
        for_each_face_node(l, side, [&](int i, const Vec& x, const Vec&, const Vec&) {
          const auto* bc = bs.at(x, l);
          if (!bc) return;
          const double before = injected ? v.col(i).squaredNorm() : 0.0;
          if (bc->kind == BoundaryKind::fixed) v.col(i).setZero();
          if (bc->kind == BoundaryKind::velocity) v.col(i) = bc->value(t);
          if (bc->kind == BoundaryKind::roller) v(l, i) = 0.0;
          if (injected) *injected += 0.5 * mass_[i] * (v.col(i).squaredNorm() - before);
        });
      }
    }
  }

  // A prescribed (sigma_nn, sigma_nt) on a face acts on the body as the traction sigma n: + at
  // the upper face, - at the lower one; each node takes the integral of its shape function over
  // the loaded part of the face. Massless nodes carry no material.
  void add_traction(double t) {
    for (int l = 0; l < Dim; ++l) {
      if (grid_.periodic[l]) continue;
      for (int side = 0; side < 2; ++side) {
        for (const auto& s : bc_[l][side].segments) {
          if (s.condition.kind != BoundaryKind::traction) continue;
          const Vec value = s.condition.value(t);
          Vec traction = Vec::Zero();
          traction[l] = value[0];
          if constexpr (Dim > 1) traction[1 - l] = value[1];
          if (!side) traction = -traction;
          for_each_face_node(l, side, [&](int i, const Vec& x, const Vec& lo, const Vec& hi) {
            if (mass_[i] <= 0.0) return;
            const Vec f = face_weight(x, lo, hi, s, l) * traction;
            force_.col(i) += f;
            loaded_nodes_.emplace_back(i, f);
          });
        }
      }
    }
  }

  double load_work_ = 0;
  std::vector<std::pair<int, Vec>> loaded_nodes_;  // traction forces of this step
  Grid<Dim> grid_;
  Boundaries<Dim> bc_;
  std::vector<Material> materials_;
  MpmVariant variant_;
  MpmVelocityUpdate update_;
  std::array<int, Dim> nodes_{}, stride_{};
  int num_nodes_ = 0;

  Eigen::Matrix<int, npc, Eigen::Dynamic> node_;
  Eigen::VectorXi block_;  // the scatter block of the particle's cell
  Eigen::Matrix<double, npc, Eigen::Dynamic> shape_;
  Eigen::Matrix<double, npc * Dim, Eigen::Dynamic> grad_;  // row a * Dim + l: dS_a / dx_l
  Eigen::VectorXd mass_;
  NodalVectors vel_old_, vel_new_, vel_musl_, force_;
};

}  // namespace dgmpm
