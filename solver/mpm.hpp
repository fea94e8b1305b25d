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
    inverse_h_ = grid_.cell_size.cwiseInverse();
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

  // One step from t to t + dt; returns whether every new particle state is finite (each pass
  // back to the particles checks the states it writes). Allocation-free once the particle count
  // is reached. Throws ParticleOutsideGrid for a particle outside the grid, before any change at
  // the start of the step, or after the move that took it out.
  // The transfers are fused: one scatter to the grid of mass, momentum and (USL, MUSL) internal
  // force, one pass over the nodes for v^n and v^{n+1} (USL, MUSL), one pass back to the
  // particles of velocity, stress (USL, USF) and position. Particles that do not move are located
  // once: their nodes and cell coordinates are kept from step to step (as DGMPM keeps its cell
  // lists), until a step moves them or relocate().
  bool step(ParticleSet& particles, double t, double dt, bool move_particles) {
    const bool usf = variant_ == MpmVariant::usf, musl = variant_ == MpmVariant::musl;
    if (!located_ || node_.cols() != particles.size()) locate(particles);
    if (move_particles) located_ = false;  // located again next step, even if this one throws
    const int np = particles.size();
    vel_new_.resize(Dim, num_nodes_);
    loaded_nodes_.clear();
    zero_nodes(vel_old_, &force_, np);
    project_mass_momentum(particles, vel_old_, !usf);
    if (usf) {  // v^n constrained, the stress from it, then its force
      nodal_velocities(vel_old_, nullptr, dt, np);
      apply_velocity_bc(vel_old_, t, &load_work_);
      to_particles(particles, dt, {.stress_from = &vel_old_});
      scatter(np, [&](int p) { add_internal_force(particles, p); });
      add_traction(t);
#pragma omp parallel for schedule(static) if (threaded(np))
      for (int i = 0; i < num_nodes_; ++i) vel_new_.col(i) = advanced(i, vel_old_.col(i), dt);
    } else {  // v^n and v^{n+1} in one pass (the constraints on v^n change no free v^{n+1})
      add_traction(t);
      nodal_velocities(vel_old_, &vel_new_, dt, np);
      apply_velocity_bc(vel_old_, t, &load_work_);
    }
    for (const auto& [i, f] : loaded_nodes_)
      load_work_ += 0.5 * dt * f.dot(vel_old_.col(i) + vel_new_.col(i));
    apply_velocity_bc(vel_new_, t + dt, &load_work_);
    if (!musl)
      return to_particles(particles, dt,
                          {.velocity = true,
                           .stress_from = usf ? nullptr : &vel_new_,
                           .move_with = move_particles ? &vel_new_ : nullptr});
    // MUSL: the new particle velocities projected again, then stress and move from them.
    to_particles(particles, dt, {.velocity = true});
    zero_nodes(vel_musl_, nullptr, np);
    project_mass_momentum(particles, vel_musl_, false);
    nodal_velocities(vel_musl_, nullptr, dt, np);
    apply_velocity_bc(vel_musl_, t + dt);
    return to_particles(
        particles, dt,
        {.stress_from = &vel_musl_, .move_with = move_particles ? &vel_musl_ : nullptr});
  }

  // The particles changed other than by step (a restart): locate them at the next step.
  void relocate() {
    located_ = false;
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
    const auto g = gradients(p);
    for (int a = 0; a < npc; ++a) grad.noalias() += v.col(node_(a, p)) * g.col(a).transpose();
    auto q = ps.state.col(p);
    Physics::add_stress_rate(q, grad, materials_[ps.material[p]], dt);
    if constexpr (physics::ParticleStepPhysics<Physics>)
      Physics::particle_step(q, ps.internal.col(p), materials_[ps.material[p]], dt);
  }
  // f_i -= V_p sigma_p grad S_i(x_p) at the nodes of particle p.
  void add_internal_force(const ParticleSet& ps, int p) {
    const Tensor vs =
        ps.volume[p] * Physics::stress_tensor(ps.state.col(p), materials_[ps.material[p]]);
    const auto g = gradients(p);
    for (int a = 0; a < npc; ++a) force_.col(node_(a, p)).noalias() -= vs * g.col(a);
  }

  // --- generic part ------------------------------------------------------------------------------
  bool threaded(int np) const {
    return np >= kThreadedParticles;
  }
  // Shape values and gradients at particle p, from its cell coordinates (as cheap to compute as
  // to read: 12 numbers in 2D against 2).
  typename CellShape<Dim>::Values shape(int p) const {
    return CellShape<Dim>::values(xi_.col(p));
  }
  typename CellShape<Dim>::Gradients gradients(int p) const {
    return CellShape<Dim>::gradients(xi_.col(p), inverse_h_);
  }

  // Calls add(p) for every particle p, on threads where there are many, each node receiving its
  // particles in the same order whatever their number. The layers of cells along the last axis
  // (rows) are grouped into kScatterBlocks blocks of consecutive rows, coloured even and odd (and
  // a periodic axis' last block alone when their count is odd: it shares nodes with block 0). Two
  // blocks of a colour share no node, so a colour's blocks are split between the threads; a node
  // receives a colour's particles from one block, in particle order (locate lists each block's
  // particles in that order: a thread reads only its blocks' particles).
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
        for (int b = mine.begin; b < mine.end; ++b)
          if (colour(b) == c)
            for (int e = block_begin_[b]; e < block_begin_[b + 1]; ++e) add(by_block_[e]);
#pragma omp barrier
      }
    }
  }

  // Nodes and cell coordinates of every particle, and the particles of each scatter block
  // in particle order (a stable counting sort: each thread counts its share's blocks, then places
  // its share after the shares before it in each block).
  void locate(const ParticleSet& ps) {
    const int np = ps.size();
    node_.resize(npc, np);
    xi_.resize(Dim, np);
    block_.resize(np);
    by_block_.resize(np);
    const int blocks = scatter_blocks();
    const long rows = grid_.cells[Dim - 1];
    int threads = 1;
#ifdef _OPENMP
    if (threaded(np)) threads = omp_get_max_threads();
#endif
    block_begin_.resize(blocks + 1);
    block_place_.resize(static_cast<std::size_t>(threads) * blocks);
    int outside = np;  // the first particle outside the grid
#pragma omp parallel num_threads(threads) if (threads > 1) reduction(min : outside)
    {
      const TeamPlace place = team_place();
      const Share share = thread_share(np, place);
      int* count = block_place_.data() + static_cast<std::size_t>(place.thread) * blocks;
      std::fill(count, count + blocks, 0);
      for (int p = share.begin; p < share.end; ++p) {
        Vec xi;
        const int c = grid_.locate(ps.position.col(p), xi);
        if (c < 0) {
          outside = std::min(outside, p);
          block_[p] = -1;  // placed nowhere: the step throws
          continue;
        }
        xi_.col(p) = xi;
        const auto k = grid_.unflatten(c);
        block_[p] = static_cast<int>(k[Dim - 1] * blocks / rows);
        ++count[block_[p]];
        for (int a = 0; a < npc; ++a) node_(a, p) = node(k, a);
      }
#pragma omp barrier
#pragma omp single
      {
        int next = 0;  // block by block, each thread's share in thread order
        for (int b = 0; b < blocks; ++b) {
          block_begin_[b] = next;
          for (int t = 0; t < place.team; ++t) {
            int& place_of = block_place_[static_cast<std::size_t>(t) * blocks + b];
            const int n = place_of;
            place_of = next;
            next += n;
          }
        }
        block_begin_[blocks] = next;
      }  // (an implicit barrier)
      for (int p = share.begin; p < share.end; ++p)
        if (block_[p] >= 0) by_block_[count[block_[p]]++] = p;
    }
    if (outside < np) throw_outside_grid(ps, outside);
    located_ = true;
  }

  // Nodal mass, momentum v and (when given) force zeroed in one pass, on the threads (three
  // serial fills were 8% of a USL step on one thread, and not shared on two).
  void zero_nodes(NodalVectors& v, NodalVectors* force, int np) {
    mass_.resize(num_nodes_);
    v.resize(Dim, num_nodes_);
    if (force) force->resize(Dim, num_nodes_);
#pragma omp parallel for schedule(static) if (threaded(np))
    for (int i = 0; i < num_nodes_; ++i) {
      mass_[i] = 0.0;
      v.col(i).setZero();
      if (force) force->col(i).setZero();
    }
  }

  // Lumped mass and nodal momentum p_i, and with `force` the internal force, in one scatter (onto
  // zeroed nodes).
  void project_mass_momentum(const ParticleSet& ps, NodalVectors& v, bool force) {
    const int np = ps.size();
    scatter(np, [&](int p) {
      const Vec vp = particle_velocity(ps, p);
      const auto s = shape(p);
      for (int a = 0; a < npc; ++a) {
        const int i = node_(a, p);
        const double w = s[a] * ps.mass[p];
        mass_[i] += w;
        v.col(i) += w * vp;
      }
      if (force) add_internal_force(ps, p);
    });
  }

  // v^{n+1} of node i before the constraints, from its v^n (zero on a massless node).
  Vec advanced(int i, const Vec& v, double dt) const {
    return mass_[i] > 0.0 ? Vec(v + (dt / mass_[i]) * force_.col(i)) : Vec::Zero();
  }
  // The momenta v become velocities p_i / m_i (zero on massless nodes) and, with `next`, next
  // gets their advanced velocities, in the same pass.
  void nodal_velocities(NodalVectors& v, NodalVectors* next, double dt, int np) const {
#pragma omp parallel for schedule(static) if (threaded(np))
    for (int i = 0; i < num_nodes_; ++i) {
      if (mass_[i] > 0.0) v.col(i) /= mass_[i];
      if (next) next->col(i) = advanced(i, v.col(i), dt);
    }
  }

  // What to_particles does at each particle, in this order: the velocity update (FLIP adds the
  // interpolated nodal velocity increment, PIC takes the interpolated velocity), the stress
  // update from the nodal velocities `stress_from`, the move with `move_with` (none when null).
  struct ToParticles {
    bool velocity = false;
    const NodalVectors* stress_from = nullptr;
    const NodalVectors* move_with = nullptr;
  };
  // One pass over the particles; returns whether the states it leaves are finite (0 x summed
  // without a branch: 0 for finite x, NaN otherwise). Throws ParticleOutsideGrid for the first
  // particle moved out.
  bool to_particles(ParticleSet& ps, double dt, const ToParticles& what) const {
    const bool flip = update_ == MpmVelocityUpdate::flip;
    const int np = ps.size();
    int outside = np;  // the first particle outside the grid
    double nonfinite = 0;
#pragma omp parallel for schedule(static) reduction(min : outside) reduction(+ : nonfinite) \
    if (threaded(np))
    for (int p = 0; p < np; ++p) {
      const auto s = shape(p);
      if (what.velocity) {
        Vec v = Vec::Zero();
        for (int a = 0; a < npc; ++a) {
          const int i = node_(a, p);
          v += s[a] * (flip ? Vec(vel_new_.col(i) - vel_old_.col(i)) : Vec(vel_new_.col(i)));
        }
        set_particle_velocity(ps, p, flip ? Vec(particle_velocity(ps, p) + v) : v);
      }
      if (what.stress_from) update_stress(ps, p, *what.stress_from, dt);
      if (what.move_with) {
        Vec vp = Vec::Zero();
        for (int a = 0; a < npc; ++a) vp += s[a] * what.move_with->col(node_(a, p));
        ps.position.col(p) += dt * vp;
        Vec xi;
        if (grid_.locate(ps.position.col(p), xi) < 0) outside = std::min(outside, p);
      }
      // One component at a time: a packet load across the scalar stores just made to the state
      // waits for them (no store forwarding: the pass took 1.3x as long).
      for (int k = 0; k < ncomp; ++k) nonfinite += 0.0 * ps.state(k, p);
    }
    if (outside < np) throw_outside_grid(ps, outside);
    return nonfinite == 0.0;
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
  Eigen::VectorXi block_;     // the scatter block of the particle's cell
  Eigen::VectorXi by_block_;  // the particles, block by block (from block_begin_[b])
  std::vector<int> block_begin_, block_place_;  // block_place_: locate's counts per thread
  bool located_ = false;  // node_, xi_ and by_block_ are those of the particles
  Eigen::Matrix<double, Dim, Eigen::Dynamic> xi_;  // in the cell, in [0, 1]^Dim
  Vec inverse_h_;
  Eigen::VectorXd mass_;
  NodalVectors vel_old_, vel_new_, vel_musl_, force_;
};

}  // namespace dgmpm
