#pragma once
// The DGMPM operators on one particle configuration (docs/method.md, "Discretisation"):
//   project      particles -> nodes, mass weighted: m_i q_i = sum_p S_ip m_p q_p
//   residual     r_i = sum_l K^l_ij F^s_l(q_j) + Fhat_i (pseudo-stiffness + Godunov edge fluxes)
//   update       q_i += dt r_i / m_i
//   interpolate  nodes -> particles: q_p = sum_i S_ip q_i
// The time integrators (time_integration.hpp) step through stages that do these cell by cell in
// one pass over the cells; the solver and the stability analysis both step through them.
//
// Edge fluxes: one Riemann problem per cell edge (face in 3D) between the averages of the nodal
// states that meet there; the flux is constant along the edge and each face node of each side
// receives an equal share of it. DCU uses it as it is. CTU adds the transverse corrections of
// corner transport upwind: every fluctuation entering a cell is split into waves along the other
// axes, which correct the star states of that cell's transverse edges (times dt / (2 h)). At a
// boundary edge (grid side or void neighbour) the solution beyond continues as the mirror image
// of the cell under the boundary's reflection, so that edge also receives the reflected
// fluctuation's part coming back in.

#include "boundary.hpp"
#include "discretisation.hpp"
#include "faces.hpp"
#include "grid.hpp"
#include "physics/contract.hpp"
#include "thread_share.hpp"

#include <Eigen/Core>
#include <algorithm>
#include <array>
#ifdef _OPENMP
#include <omp.h>
#endif
#include <stdexcept>
#include <type_traits>
#include <utility>
#include <vector>

namespace dgmpm {

// A cell filter that takes every cell.
struct EveryCell {
  bool operator()(int) const { return true; }
};

// What a step does at each particle after its new state is interpolated, in the same sweep: a
// constitutive correction (a plastic return) of particle p's state q. Elastic materials have none.
struct NoParticleStep {
  template <class Q>
  void operator()(int, Q&&) const {}
};

// Donor-cell upwind (normal Riemann problems only) or corner transport upwind.
enum class FluxScheme { dcu, ctu };

inline const char* to_string(FluxScheme f) {
  return f == FluxScheme::ctu ? "ctu" : "dcu";
}

template <physics::DGPhysics Physics>
class DGOperator {
 public:
  static constexpr int dim = Physics::dim;
  static constexpr int npc = 1 << dim;
  static constexpr int face_nodes = npc / 2;
  static constexpr int ncomp = Physics::n_comp;
  // Whether the physics provides CTU's parts (2D only; finite strain does not).
  static constexpr bool corner_transport = dim > 1 && physics::CornerTransport<Physics>;
  // Grids from this many cells step on threads (below, a parallel region costs more than it saves:
  // two threads against one, `dgmpm bench`, 1D RK2 1.5x at 128 cells, 1.7x at 256, 2D one particle
  // per cell 1.9x at 900).
  static constexpr int kThreadedCells = 256;
  using State = typename Physics::State;
  using Material = typename Physics::Material;
  using NodalField = Eigen::Matrix<double, ncomp, Eigen::Dynamic>;
  using ParticleField = Eigen::Matrix<double, ncomp, Eigen::Dynamic>;
  using Disc = Discretisation<Physics>;
  using Vec = Eigen::Matrix<double, dim, 1>;

  DGOperator(const Grid<dim>& grid, const Disc& disc, const Boundaries<dim>& boundaries,
             FluxScheme flux = FluxScheme::dcu)
      : grid_(grid), disc_(disc), scheme_(dim > 1 ? flux : FluxScheme::dcu), faces_(grid),
        boundary_(grid, faces_, boundaries) {
    if (scheme_ == FluxScheme::ctu && !corner_transport)
      throw std::invalid_argument("flux \"ctu\": this physics has no corner transport");
    for (int l = 0; l < dim; ++l) {
      face_weight_[l] = 1.0;
      for (int k = 0; k < dim; ++k)
        if (k != l) face_weight_[l] *= grid.cell_size[k];
      face_weight_[l] /= face_nodes;  // lumped edge integral: an equal share per face node
      if (scheme_ == FluxScheme::ctu) {
        star_[l].resize(ncomp, num_faces(l));
        fluctuation_[l].resize(ncomp, 2 * num_faces(l));
      }
    }
  }

  const Grid<dim>& grid() const { return grid_; }
  const Disc& discretisation() const { return disc_; }
  int num_nodes() const { return grid_.num_nodes(); }
  int num_faces(int axis) const { return faces_.num_faces(axis); }

  // The sweeps below run on OpenMP threads on large grids, over contiguous ranges of cells. A cell
  // writes only its own nodes (broken shape functions) and particles, a face its own star state
  // and fluctuations; every sum runs in the same order whatever the threads: the results do not
  // depend on their number.
  bool threaded() const { return disc_.num_cells() >= kThreadedCells; }

  // --- The stages the integrators step through, each one pass over the cells (sweep_cells): a
  // cell's nodal values are projected from its particles a few layers of cells ahead of the sweep
  // (as far as the cells that read them), and each cell computes its whole residual (volume term
  // and its faces' fluxes, each interior face's solved once, by the first of its two cells a
  // thread reaches) and its update, then its particles; no nodal residual array, no clearing
  // pass. CTU's star states and the fluctuations entering each side of a face are computed
  // further ahead, by the face's plus cell: a face's transverse correction gathers those of its
  // two cells' other faces. The sums are those of the face-by-face composition project ->
  // residual -> update -> interpolate in the same order: the same values to the last bit (that
  // composition is ReferenceStepper, reference_stepper.hpp). Stages that write particles
  // return whether every new state is finite.

  // Euler: q = projection of qp, then qp of each cell = interpolation of q + dt M^-1 r(q, t),
  // then `particle_step` at each of its particles.
  template <class ParticleStep = NoParticleStep>
  bool project_and_advance_to_particles(ParticleField& qp, const Eigen::VectorXd& mass, double t,
                                        double dt, NodalField& q,
                                        const ParticleStep& particle_step = {}) const {
    q.resize(ncomp, num_nodes());
    return advance(Projection{&qp, &q}, mass, q, t, dt, [&](int c, CellBlock& out, Sweep& sweep) {
      interpolate_cell(c, out, qp, particle_step, [&](const auto& s) { sweep.check(s); });
    });
  }

  // RK2's first stage: q0 = projection of qp, q1 = q0 + dt M^-1 r(q0, t) on every occupied cell.
  // At a near-empty node (Discretisation::stage_share) the residual over the node's small mass
  // makes q1 large where the cell's volume term and fluxes do not cancel, and the second stage
  // would carry it through the node's faces into the neighbours (growth like C^2 / share, near
  // faces and corners). There q1 holds the state the second stage evaluates its residual at,
  // q0 + w (q1 - q0) with w = share / stage_share, and `excess` the rest, (1 - w) (q1 - q0),
  // which the second stage adds back: the step stays conservative and second order where w = 1.
  // `excess` is written only in cells with such a node.
  void project_and_advance(const ParticleField& qp, const Eigen::VectorXd& mass, double t,
                           double dt, NodalField& q0, NodalField& q1, NodalField& excess) const {
    q0.resize(ncomp, num_nodes());
    q1.resize(ncomp, num_nodes());
    const bool damped = disc_.has_near_empty_nodes();
    if (damped) excess.resize(ncomp, num_nodes());
    advance(Projection{&qp, &q0}, mass, q0, t, dt, [&](int c, CellBlock& out, Sweep&) {
      if (damped && disc_.near_empty(c)) damp_near_empty(c, q0, out, excess);
      q1.template middleCols<npc>(c * npc) = out;
    });
  }

  // RK2's second stage (Heun): qp = interpolation of (q0 + q1 + dt M^-1 r(q1, t)) / 2, plus the
  // first stage's excess at near-empty nodes, then `particle_step` at each particle.
  template <class ParticleStep = NoParticleStep>
  bool average_to_particles(const NodalField& q0, const NodalField& q1, const NodalField& excess,
                            const Eigen::VectorXd& mass, double t, double dt, ParticleField& qp,
                            const ParticleStep& particle_step = {}) const {
    const bool damped = disc_.has_near_empty_nodes();
    return advance(Projection{}, mass, q1, t, dt, [&](int c, CellBlock& out, Sweep& sweep) {
      out = 0.5 * (q0.template middleCols<npc>(c * npc) + out);
      if (damped && disc_.near_empty(c)) out += 0.5 * excess.template middleCols<npc>(c * npc);
      interpolate_cell(c, out, qp, particle_step, [&](const auto& s) { sweep.check(s); });
    });
  }

  // --- The parts of the residual r_i = sum_l K^l_ij F^s_l(q_j) + Fhat_i, each defined once: the
  // stages above compose them cell by cell; ReferenceStepper composes them face by face.
  using CellBlock = Eigen::Matrix<double, ncomp, npc>;
  using FaceFluctuations = std::array<NodalField, dim>;  // per axis, columns 2 f + side

  std::pair<int, int> face_cells(int l, int f) const { return faces_.cells(l, f); }
  // Each face node's share of the lumped edge integral.
  double face_weight(int l) const { return face_weight_[l]; }

  // rc += sum_l F^s_l(q) K^l^T: cell c's volume term from its nodal values q (npc columns),
  // `mass` the particles' masses.
  // A 2D cell of one particle (Discretisation::rank_one_cheaper) sums the products without
  // forming K^l; where the flux is linear (physics::LinearFlux), F_l S_p is the flux of the state
  // q S_p, without the nodes' fluxes.
  template <class Block>
  void add_volume_term(int c, const Block& q, const Eigen::VectorXd& mass, CellBlock& rc) const {
    const auto& mat = disc_.cell_material(c);
    const bool rank_one = Disc::rank_one_cheaper(disc_.cell_end(c) - disc_.cell_begin(c));
    if constexpr (physics::LinearFlux<Physics>) {
      if (rank_one) {
        disc_.add_stiffness_products(
            c, mass,
            [&](const auto& w) {
              const State at = q * w;
              std::array<State, dim> f;
              for (int l = 0; l < dim; ++l) f[l] = Physics::specific_flux(l, at, mat);
              return f;
            },
            rc);
        return;
      }
    }
    std::array<CellBlock, dim> flux;
    for (int l = 0; l < dim; ++l)
      for (int a = 0; a < npc; ++a) flux[l].col(a) = Physics::specific_flux(l, q.col(a), mat);
    if (rank_one) {
      disc_.add_stiffness_products(
          c, mass,
          [&](const auto& w) {
            std::array<State, dim> f;
            for (int l = 0; l < dim; ++l) f[l] = flux[l] * w;
            return f;
          },
          rc);
      return;
    }
    const auto apply = [&](const std::array<typename Disc::Stiffness, dim>& stiffness) {
      for (int l = 0; l < dim; ++l) rc.noalias() += flux[l] * stiffness[l].transpose();
    };
    if (disc_.shares_layout(c))
      apply(disc_.shared_stiffness());  // read in place, not copied
    else
      apply(disc_.stiffness(c, mass));
  }

  // Star state of face f along l from the edge states of its sides (a boundary state where one
  // side has no particles); false when neither side is occupied.
  bool face_star(int l, int f, const NodalField& qn, double t, State& star) const {
    const auto [cm, cp] = faces_.cells(l, f);
    const bool here = occupied(cm), there = occupied(cp);
    if (!here && !there) return false;
    const State minus = here ? edge_state(qn, cm, l, 1) : State::Zero();
    const State plus = there ? edge_state(qn, cp, l, 0) : State::Zero();
    star = star_of(l, f, here ? &minus : nullptr, there ? &plus : nullptr, t);
    return true;
  }

  // (The CTU helpers below are forced inline: left to the compiler's heuristics, their inlining
  // changed with unrelated code in the same build, and the 2D CTU RK2 step lost 10-15%.)

  // CTU: the fluctuation entering face f's occupied side (0: the minus cell, A^-dq; 1: the plus
  // cell, A^+dq) from its star state, times dt / (2 h_l).
  [[gnu::always_inline]] inline State entering_fluctuation(int l, int f, const State& star,
                                                           const NodalField& qn, double dt,
                                                           int side) const
      requires(corner_transport) {
    const auto [cm, cp] = faces_.cells(l, f);
    const int c = side ? cp : cm;
    return (dt / (2.0 * grid_.cell_size[l])) *
           Physics::fluctuation(l, star, edge_state(qn, c, l, !side), disc_.cell_material(c), side);
  }

  // CTU: the correction of face g's star state (g normal to t): each fluctuation w that entered
  // one of g's cells through a face normal to another axis sends transverse waves across g, split
  // in the media of g's two sides (transverse_medium, each taken once). Against a boundary (grid
  // side or void cell) the mirror image of the cell sends its part back in. The split is linear
  // in w (physics::CornerTransport): a cell's entering fluctuations are summed and split once.
  // Reads only the fluctuations entering g's occupied cells, and (physics whose waves depend on
  // the state) their edge states at g. `both_occupied`: the caller knows g's two cells are.
  template <bool both_occupied = false>
  [[gnu::always_inline]] inline State transverse_correction(int t, int g, const FaceFluctuations& w,
                                                            const NodalField& qn) const
      requires(corner_transport) {
    State correction = State::Zero();
    const auto [gm, gp] = faces_.cells(t, g);
    const bool occupied_minus = both_occupied || occupied(gm),
               occupied_plus = both_occupied || occupied(gp);
    // An empty side's medium is never read: it stands in as the other side's.
    const auto& minus =
        occupied_minus ? transverse_medium(t, gm, 1, qn) : transverse_medium(t, gp, 0, qn);
    const auto& plus = occupied_plus ? transverse_medium(t, gp, 0, qn) : minus;
    for (int up = 1; up >= 0; --up) {  // g: the upper face of its minus cell, the lower of its plus
      const int c = up ? gm : gp;
      if (!(up ? occupied_minus : occupied_plus)) continue;
      const auto& here = up ? minus : plus;
      State entering = State::Zero();
      for (int l = 0; l < dim; ++l) {
        if (l == t) continue;
        for (int side = 0; side < 2; ++side) {
          // c's face on `side` along l; c is its plus cell when it is c's lower face.
          const int f = faces_.of_cell(l, c, side);
          entering += w[l].col(2 * f + (side == 0));
        }
      }
      if (up ? occupied_plus : occupied_minus)
        correction -= Physics::transverse(t, entering, here, up ? plus : minus, up);
      else
        correction -= Physics::transverse_at_boundary(boundary_.kind(t, g), t, entering, here, up);
    }
    return correction;
  }

  // CTU: the medium cell c's transverse waves cross its face on `side` along t in: its material,
  // or what the physics makes of its edge state there.
  [[gnu::always_inline]] inline decltype(auto) transverse_medium(int t, int c, int side,
                                                                 const NodalField& qn) const {
    if constexpr (physics::StateDependentTransverse<Physics>)
      return Physics::transverse_medium(t, edge_state(qn, c, t, side), disc_.cell_material(c));
    else
      return (disc_.cell_material(c));
  }

  // Power delivered to the particles by the prescribed boundary loads at time t: the sum over
  // loaded boundary edges (traction, velocity) of (sigma* n) . v* times the edge length, from
  // the particle states qp projected onto those edges' cells only (no pass over the others).
  // Only the cells `counted` accepts (a distributed run counts the cells its rank owns).
  template <class Counted = EveryCell>
  double boundary_power(const ParticleField& qp, const Eigen::VectorXd& mass, double t,
                        Counted counted = {}) const {
    double power = 0.0;
    Eigen::Matrix<double, ncomp, npc> q;
    for (const auto& [l, f] : boundary_.loaded()) {
      const auto [cm, cp] = faces_.cells(l, f);
      const int c = cm >= 0 ? cm : cp;
      if (!disc_.occupied(c) || !counted(c)) continue;
      project_cell(c, qp, mass, q);
      const int side = cm >= 0 ? 1 : 0;  // the cell's side the edge is on
      const auto& mat = disc_.cell_material(c);
      const State star = boundary_star(l, f, edge_average(q, l, side), mat, side, t);
      // -F_n's momentum rows are sigma* e_l; along the outward normal (+-e_l), times v*.
      const State fl = Physics::flux(l, star, mat);
      double p = 0;
      for (int k = 0; k < dim; ++k) p -= fl[ncomp - dim + k] * star[ncomp - dim + k];
      power += (side ? 1.0 : -1.0) * edge_length(l) * p;
    }
    return power;
  }

 private:
  // RK2's first stage at cell c's near-empty nodes (project_and_advance): out becomes the damped
  // state, excess the rest. A massless node keeps the copy of its stand-in.
  void damp_near_empty(int c, const NodalField& q0, CellBlock& out, NodalField& excess) const {
    const double cell = disc_.cell_mass(c);
    for (int a = 0; a < npc; ++a) {
      const int i = c * npc + a;
      const double share = disc_.node_mass(i) / cell;
      const double w = disc_.source_corner(i) == a
                           ? std::min(1.0, share / Discretisation<Physics>::stage_share)
                           : 1.0;
      excess.col(i) = (1.0 - w) * (out.col(a) - q0.col(i));
      out.col(a) -= excess.col(i);
    }
  }

  // Cell c's particles from its nodal values, then `particle_step` at each; `check` sees each new
  // state as it is written.
  template <class Block, class ParticleStep, class Check>
  void interpolate_cell(int c, const Block& block, ParticleField& qp,
                        const ParticleStep& particle_step, const Check& check) const {
    const int begin = disc_.cell_begin(c), end = disc_.cell_end(c);
    const auto each = [&](int e, const auto& shape) {
      const int p = disc_.entry_particle(e);
      qp.col(p).noalias() = block * shape;
      if constexpr (!std::is_same_v<ParticleStep, NoParticleStep>) particle_step(p, qp.col(p));
      check(qp.col(p));
    };
    if (disc_.shares_layout(c))
      for (int e = begin; e < end; ++e) each(e, disc_.shared_shape(e - begin));
    else
      for (int e = begin; e < end; ++e) each(e, disc_.entry_shape(e));
  }

  // A thread's sweep over its contiguous range of cells [begin, end), in order. The star state of
  // each cell's upper face along l is kept (slot c mod stride_l of that axis) for the cell above
  // along l, whose lower face it is: each interior face's Riemann problem is solved once.
  struct Sweep {
    int begin = 0, end = 0;
    std::array<State*, dim> stars{};
    std::array<int, dim> slot{};  // c mod stride_l, kept by the loop (no division per cell)
    // 0 * x is 0 for finite x, NaN otherwise: summed over the checked states, without a branch.
    // A stage checks its new particle states, after the particle step (fewer values than the
    // cell's nodes at one or two particles per cell; a nonfinite node reaches every particle of
    // its cell).
    State nonfinite = State::Zero();
    template <class S>
    void check(const S& state) {
      nonfinite += 0.0 * state;
    }
  };

  // Particles projected by a sweep on the fly (none when qp is null).
  struct Projection {
    const ParticleField* qp = nullptr;
    NodalField* q = nullptr;
  };

  // Work a sweep does on cell c + lead before the body of c. A thread does it before its sweep
  // (then waits for the others) on the cells other threads read: the first `lead` and the last
  // `tail` cells of its range.
  template <class Work>
  struct Ahead {
    int lead, tail;
    Work work;
  };
  // (A function rather than deduction from the aggregate: clang 14 deduces neither for a member
  // template of a class template.)
  template <class Work>
  static Ahead<Work> ahead(int lead, int tail, Work work) {
    return {lead, tail, work};
  }

  // One stage: out = q_c + dt M^-1 r_c(from, t) on every occupied cell c, then finish(c, out,
  // sweep). How far ahead the projection and CTU's faces run: the cells a face links are at most
  // `reach` apart in index (the largest stride; a periodic wrap along the last axis links the
  // grid's first and last layers, which the first and last threads do before their sweeps). A
  // CTU body reads the faces of its cell and of its face neighbours (a wrap along another axis
  // included: less than `reach` away), each owned by its plus cell: less than 2 reach from it,
  // ahead or behind; a face reads the cells within reach of its owner.
  // (The per-cell work is flattened: every call in it inlined, the physics' Riemann solver, fluxes
  // and fluctuations included, which the compiler otherwise left as calls with the axis a
  // variable. Callgrind, instructions per particle-step: 1D Euler 557 -> 524, 2D DCU Euler at one
  // particle per cell 2127 -> 2089, CTU Euler 4075 -> 3342.)
  template <class Finish>
  bool advance(const Projection& projection, const Eigen::VectorXd& mass, const NodalField& from,
               double t, double dt, Finish&& finish) const {
    const auto project_one = [&](int c) __attribute__((flatten)) {
      if (disc_.occupied(c))
        project_cell(c, *projection.qp, mass, projection.q->template middleCols<npc>(c * npc));
    };
    const int reach = faces_.stride(dim - 1);
    if (scheme_ == FluxScheme::dcu) {
      const auto body = [&](int c, Sweep& sweep) __attribute__((flatten)) {
        CellBlock out;
        advance_cell<FluxScheme::dcu>(c, from, mass, t, dt, sweep, out);
        finish(c, out, sweep);
      };
      const auto run = interior_run<FluxScheme::dcu>(from, mass, dt, finish);
      if (!projection.qp) return sweep_cells(body, interior_runs(run));
      return sweep_cells(body, interior_runs(run), ahead(reach, reach, project_one));
    }
    if constexpr (corner_transport) {
      const auto body = [&](int c, Sweep& sweep) __attribute__((flatten)) {
        CellBlock out;
        advance_cell<FluxScheme::ctu>(c, from, mass, t, dt, sweep, out);
        finish(c, out, sweep);
      };
      const auto faces = [&](int c) __attribute__((flatten)) {
        own_faces(c, from, t, dt);
      };
      const auto run = interior_run<FluxScheme::ctu>(from, mass, dt, finish);
      if (!projection.qp)
        return sweep_cells(body, interior_runs(run), ahead(2 * reach, 2 * reach, faces));
      return sweep_cells(body, interior_runs(run), ahead(3 * reach, 3 * reach, project_one),
                         ahead(2 * reach, 2 * reach, faces));
    }
    return true;
  }

  // A run of consecutive interior cells [c, e), in one call: each cell's work ahead
  // (before_cell), its interior step and finish, then the sweep's next cell (next_cell).
  // (Everything by reference, dt included: the caller's objects, which outlive its sweep.)
  template <FluxScheme scheme, class Finish>
  auto interior_run(const NodalField& from, const Eigen::VectorXd& mass, const double& dt,
                    Finish& finish) const {
    return [&](int c, int e, Sweep& sweep, const auto& before_cell, const auto& next_cell)
        __attribute__((flatten)) {
      for (int k = c; k < e; ++k) {
        before_cell(k);
        CellBlock out;
        advance_interior_cell<scheme>(k, from, mass, dt, sweep, out);
        finish(k, out, sweep);
        next_cell();
      }
    };
  }

  // How a sweep steps interior cells (Discretisation::interior): by body, cell by cell, or by
  // run(c, e, sweep, before_cell, next_cell) over each run of consecutive ones.
  struct NoInteriorRuns {};
  template <class Run>
  struct InteriorRuns {
    Run run;
  };
  // (A function, as for Ahead: clang 14 deduces no aggregate of a member template.)
  template <class Run>
  static InteriorRuns<Run> interior_runs(Run run) {
    return {run};
  }

  // Calls body(c, sweep) on every occupied cell (interior cells: runs.run over their runs, when
  // given), on threads over contiguous ranges of cells, with the work ahead of it; returns whether
  // every block the bodies checked (Sweep::check) is finite.
  template <class Body, class Runs, class... Work>
  bool sweep_cells(Body&& body, const Runs& runs, const Ahead<Work>&... ahead) const {
    const int n = disc_.num_cells();
    int threads = 1;
#ifdef _OPENMP
    if (threaded()) threads = omp_get_max_threads();
#endif
    const std::size_t per_thread = star_slots_per_thread();
    if (star_cache_.size() < per_thread * threads) star_cache_.resize(per_thread * threads);
    bool finite = true;
#pragma omp parallel num_threads(threads) if (threads > 1) reduction(&& : finite)
    {
      const TeamPlace place = team_place();
      const Share share = thread_share(n, place);
      Sweep sweep;
      sweep.begin = share.begin;
      sweep.end = share.end;
      [[maybe_unused]] const auto before = [&](const auto& a) {
        const int head = std::min(sweep.begin + a.lead, sweep.end);
        for (int c = sweep.begin; c < head; ++c) a.work(c);
        for (int c = std::max(sweep.end - a.tail, head); c < sweep.end; ++c) a.work(c);
#pragma omp barrier
      };
      (before(ahead), ...);
      State* slots = star_cache_.data() + per_thread * place.thread;
      for (int l = 0; l < dim; ++l) {
        sweep.stars[l] = slots;
        slots += faces_.stride(l);
      }
      for (int l = 0; l < dim; ++l) sweep.slot[l] = sweep.begin % faces_.stride(l);
      const auto before_cell = [&](int c) {
        [[maybe_unused]] const auto during = [&](const auto& a) {
          const int x = c + a.lead;
          if (x >= sweep.begin + a.lead && x < sweep.end - a.tail) a.work(x);
        };
        (during(ahead), ...);
      };
      const auto next_cell = [&] {
        for (int l = 0; l < dim; ++l)
          if (++sweep.slot[l] == faces_.stride(l)) sweep.slot[l] = 0;
      };
      for (int c = sweep.begin; c < sweep.end;) {
        if constexpr (!std::is_same_v<Runs, NoInteriorRuns>) {
          if (disc_.interior(c)) {
            int e = c + 1;
            while (e < sweep.end && disc_.interior(e)) ++e;
            runs.run(c, e, sweep, before_cell, next_cell);
            c = e;
            continue;
          }
        }
        before_cell(c);
        if (disc_.occupied(c)) body(c, sweep);
        next_cell();
        ++c;
      }
      finite = sweep.nonfinite.allFinite();
    }
    return finite;
  }
  // Each thread's slots, then 128 bytes that no thread writes: two threads never write the same
  // cache line (in 1D a thread has a single slot, written at every cell).
  std::size_t star_slots_per_thread() const {
    std::size_t slots = 128 / sizeof(State) + 1;
    for (int l = 0; l < dim; ++l) slots += static_cast<std::size_t>(faces_.stride(l));
    return slots;
  }

  // CTU: the star states and entering fluctuations of the faces cell c owns (it is their plus
  // cell, or their only cell on a grid side), where a side is occupied. An interior cell
  // (Discretisation::interior) owns its lower faces only, each between occupied cells of its
  // material: the same Riemann problems as face_star's, without its look-ups and branches.
  [[gnu::always_inline]] inline void own_faces(int c, const NodalField& qn, double t,
                                               double dt) const {
    if (disc_.interior(c)) {
      const auto& mat = disc_.cell_material(c);
      const auto q = qn.template middleCols<npc>(c * npc);
      for_each_axis([&](auto axis) __attribute__((always_inline)) {
        constexpr int l = decltype(axis)::value;
        const State star = Physics::riemann(l, edge_state(qn, c - faces_.stride(l), l, 1), mat,
                                            edge_average(q, l, 0), mat);
        store_star(l, faces_.of_cell(l, c, 0), star, qn, dt, true, true);
      });
      return;
    }
    for_each_axis([&](auto axis) __attribute__((always_inline)) {
      constexpr int l = decltype(axis)::value;
      store_face(l, faces_.of_cell(l, c, 0), qn, t, dt);
      const int upper = faces_.of_cell(l, c, 1);
      if (faces_.cells(l, upper).second < 0) store_face(l, upper, qn, t, dt);
    });
  }
  [[gnu::always_inline]] inline void store_face(int l, int f, const NodalField& qn, double t,
                                                double dt) const {
    State star;
    if (!face_star(l, f, qn, t, star)) return;
    const auto [cm, cp] = faces_.cells(l, f);
    store_star(l, f, star, qn, dt, occupied(cm), occupied(cp));
  }
  // Face f's star state, and the fluctuations entering its sides that are occupied.
  [[gnu::always_inline]] inline void store_star(int l, int f, const State& star,
                                                const NodalField& qn, double dt, bool minus,
                                                bool plus) const {
    copy_state(star, star_[l].col(f));
    if (minus) fluctuation_[l].col(2 * f) = entering_fluctuation(l, f, star, qn, dt, 0);
    if (plus) fluctuation_[l].col(2 * f + 1) = entering_fluctuation(l, f, star, qn, dt, 1);
  }

  // Cell c's residual: the volume term, then its faces axis by axis (each node receives one face
  // per axis: the lower face's nodes have bit l clear), as the face-by-face composition sums them.
  template <FluxScheme scheme>
  [[gnu::always_inline]] inline void cell_residual(int c, const NodalField& qn,
                                                   const Eigen::VectorXd& mass, double t,
                                                   const Sweep& sweep, CellBlock& rc) const {
    rc.setZero();
    const auto& mat = disc_.cell_material(c);
    const auto q = qn.template middleCols<npc>(c * npc);
    add_volume_term(c, q, mass, rc);
    // The faces of axis l (an int, or a compile-time constant: see below).
    const auto faces_along = [&](auto axis) __attribute__((always_inline)) {
      const int l = axis;
      const double w = face_weight_[l];
      for (int up = 0; up < 2; ++up) {
        const int f = faces_.of_cell(l, c, up);
        const auto [cm, cp] = faces_.cells(l, f);
        const int o = up ? cp : cm;
        State star;
        State& slot = sweep.stars[l][sweep.slot[l]];  // o = c - stride_l shares it
        if (!up && o == c - faces_.stride(l) && o >= sweep.begin && occupied(o)) {
          star = slot;  // solved by o, as its upper face, just before
        } else if constexpr (scheme == FluxScheme::ctu) {
          star = star_[l].col(f) + transverse_correction(l, f, fluctuation_, qn);
        } else {
          // face_star's star, from this side: the same Riemann problem as the other cell solves.
          const State mine = edge_average(q, l, up);
          const State theirs = occupied(o) ? edge_state(qn, o, l, !up) : State::Zero();
          const State* other = occupied(o) ? &theirs : nullptr;
          star = up ? star_of(l, f, &mine, other, t) : star_of(l, f, other, &mine, t);
        }
        if (up) copy_state(star, slot);
        add_face_flux(l, up, w, Physics::flux(l, star, mat), rc);
      }
    };
    // In 2D with the axis a constant, as the interior path: the states stay in registers and
    // add_face_flux's nodes are known (2D DCU Euler at 1 ppc 1391 -> 1360 instructions per
    // particle-step, CTU 2702 -> 2575). In 1D the axis stays an int: the constant made the compiler
    // schedule the whole 1D sweep worse (1D Euler 1.07x the time, the same operations).
    if constexpr (dim == 1)
      faces_along(0);
    else
      for_each_axis(faces_along);
  }

  // The flux F of a face on its side `up` of axis l: rc -= w F at the upper side's nodes, += at
  // the lower's. A state wider than a packet is read coefficient by coefficient, as copy_state
  // copies it: a physics assembles F and the star states from scalars, on the stack, and a packet
  // read of them waits for those stores (store forwarding fails; 2D DCU Euler at 1 ppc: 0.84x the
  // time). A state of one packet (1D) is assembled in a register: whole-state operations.
  [[gnu::always_inline]] static inline void add_face_flux(int l, int up, double w,
                                                          const State& flux, CellBlock& rc) {
    if constexpr (ncomp <= 2) {
      const State x = w * flux;
      for (int a = 0; a < npc; ++a)
        if (((a >> l) & 1) == up) {
          if (up)
            rc.col(a) -= x;
          else
            rc.col(a) += x;
        }
      return;
    }
    for (int i = 0; i < ncomp; ++i) {
      const double x = w * flux[i];
      for (int a = 0; a < npc; ++a)
        if (((a >> l) & 1) == up) {
          if (up)
            rc(i, a) -= x;
          else
            rc(i, a) += x;
        }
    }
  }
  template <class To>
  [[gnu::always_inline]] static inline void copy_state(const State& from, To&& to) {
    if constexpr (ncomp <= 2)
      to = from;
    else
      for (int i = 0; i < ncomp; ++i) to[i] = from[i];
  }

  // out = q_c + dt M^-1 r_c: a massless node's residual goes to the node standing in for it, and
  // it copies that node's value after the update.
  template <FluxScheme scheme>
  [[gnu::always_inline]] inline void advance_cell(int c, const NodalField& qn,
                                                  const Eigen::VectorXd& mass, double t, double dt,
                                                  const Sweep& sweep, CellBlock& out) const {
    CellBlock rc;
    cell_residual<scheme>(c, qn, mass, t, sweep, rc);
    if (disc_.has_massless_nodes())
      for (int a = 0; a < npc; ++a) {
        const int s = disc_.source_corner(c * npc + a);
        if (s >= 0 && s != a) rc.col(s) += rc.col(a);
      }
    out = qn.template middleCols<npc>(c * npc);
    for (int a = 0; a < npc; ++a) out.col(a) += (dt * disc_.inverse_mass(c * npc + a)) * rc.col(a);
    for (int a = 0; a < npc; ++a) {
      const int s = disc_.source_corner(c * npc + a);
      if (s != a) out.col(a) = out.col(s);
    }
  }

  // What a sweep's run of interior cells (Discretisation::interior) steps in place of
  // advance_cell: a cell whose neighbours are c +- stride_l, occupied, of its material; no face
  // is a boundary and no node massless. The same operations in the same order as the general
  // path: the same values to the last bit (tests/solver_shared_layout.cpp).
  template <FluxScheme scheme>
  [[gnu::always_inline]] inline void
  advance_interior_cell(int c, const NodalField& qn, const Eigen::VectorXd& mass, double dt,
                        const Sweep& sweep, CellBlock& out) const {
    CellBlock rc;
    rc.setZero();
    const auto& mat = disc_.cell_material(c);
    const auto q = qn.template middleCols<npc>(c * npc);
    add_volume_term(c, q, mass, rc);
    // Axis by axis with the axis a constant: the physics' component indices are then known and
    // its states can stay in registers.
    for_each_axis([&](auto axis) __attribute__((always_inline)) {
      constexpr int l = decltype(axis)::value;
      const double w = face_weight_[l];
      const int below = c - faces_.stride(l), above = c + faces_.stride(l);
      State& slot = sweep.stars[l][sweep.slot[l]];  // below's upper face, solved just before
      // (Each scheme writes its faces out: DCU's star states through a lambda shared with CTU's
      // made the compiler emit more for 1D RK2, 576 -> 582 instructions per particle-step.)
      if constexpr (scheme == FluxScheme::dcu) {
        const State lower =
            below >= sweep.begin
                ? slot
                : Physics::riemann(l, edge_state(qn, below, l, 1), mat, edge_average(q, l, 0), mat);
        add_face_flux(l, 0, w, Physics::flux(l, lower, mat), rc);
        const State upper =
            Physics::riemann(l, edge_average(q, l, 1), mat, edge_state(qn, above, l, 0), mat);
        copy_state(upper, slot);
        add_face_flux(l, 1, w, Physics::flux(l, upper, mat), rc);
      } else {  // CTU: the stored star states with their transverse corrections
        const auto corrected = [&](int f) __attribute__((always_inline)) {
          return State(star_[l].col(f) + transverse_correction<true>(l, f, fluctuation_, qn));
        };
        const State lower = below >= sweep.begin ? slot : corrected(faces_.of_cell(l, c, 0));
        add_face_flux(l, 0, w, Physics::flux(l, lower, mat), rc);
        const State upper = corrected(faces_.of_cell(l, c, 1));
        copy_state(upper, slot);
        add_face_flux(l, 1, w, Physics::flux(l, upper, mat), rc);
      }
    });
    out = q;
    for (int a = 0; a < npc; ++a) out.col(a) += (dt * disc_.inverse_mass(c * npc + a)) * rc.col(a);
  }

  // f(std::integral_constant<int, l>) for each axis l in order.
  template <class F>
  [[gnu::always_inline]] static inline void for_each_axis(F&& f) {
    [&]<int... l>(std::integer_sequence<int, l...>) __attribute__((always_inline)) {
      (f(std::integral_constant<int, l>{}), ...);
    }
    (std::make_integer_sequence<int, dim>{});
  }

  double edge_length(int l) const {
    return face_weight_[l] * face_nodes;
  }

  // Cell c's nodal states from its particles (block: its npc columns, set here).
  template <class Block>
  void project_cell(int c, const ParticleField& qp, const Eigen::VectorXd& mass,
                    Block&& block) const {
    block.setZero();
    const int begin = disc_.cell_begin(c), end = disc_.cell_end(c);
    const auto add = [&](int e, const auto& shape) {
      const int p = disc_.entry_particle(e);
      block.noalias() += (mass[p] * qp.col(p)) * shape.transpose();
    };
    if (disc_.shares_layout(c))
      for (int e = begin; e < end; ++e) add(e, disc_.shared_shape(e - begin));
    else
      for (int e = begin; e < end; ++e) add(e, disc_.entry_shape(e));
    if (disc_.interior(c)) {  // every node its own source
      for (int a = 0; a < npc; ++a) block.col(a) *= disc_.inverse_mass(c * npc + a);
      return;
    }
    for (int a = 0; a < npc; ++a)
      if (disc_.source_corner(c * npc + a) == a) block.col(a) *= disc_.inverse_mass(c * npc + a);
    for (int a = 0; a < npc; ++a) {
      const int s = disc_.source_corner(c * npc + a);
      if (s != a) block.col(a) = block.col(s);
    }
  }

  // Average of a cell's nodal states (its npc columns) on its `side` along axis l.
  template <class Block>
  static State edge_average(const Block& q, int l, int side) {
    State s = State::Zero();
    for (int a = 0; a < npc; ++a)
      if (((a >> l) & 1) == side) s += q.col(a);
    return s * (1.0 / face_nodes);
  }
  State edge_state(const NodalField& qn, int c, int l, int side) const {
    return edge_average(qn.template middleCols<npc>(c * npc), l, side);
  }

  // Star state of boundary face f (grid side or void neighbour) from the inside edge state q of
  // the occupied cell, on its plus side (side 1: the face is its upper one) or minus side.
  State boundary_star(int l, int f, const State& q, const Material& mat, int side, double t) const {
    const auto* condition = boundary_.at(l, f);
    const BoundaryKind kind = condition ? condition->kind : BoundaryKind::free;
    const Vec value = condition ? boundary_.value(*condition, t) : Vec::Zero();
    if constexpr (physics::DirectBoundary<Physics>) {
      return Physics::boundary_star(kind, value, l, q, mat, side);
    } else {
      const State g = Physics::ghost(kind, value, l, q, mat);
      return side ? Physics::riemann(l, q, mat, g, mat) : Physics::riemann(l, g, mat, q, mat);
    }
  }

  bool occupied(int c) const {
    return c >= 0 && disc_.occupied(c);
  }

  // Star state of face f along l from the edge states of its sides: the minus cell's upper edge
  // and the plus cell's lower edge, nullptr for a side without particles (not both).
  [[gnu::always_inline]] inline State star_of(int l, int f, const State* minus, const State* plus,
                                              double t) const {
    const auto [cm, cp] = faces_.cells(l, f);
    if (minus && plus)
      return Physics::riemann(l, *minus, disc_.cell_material(cm), *plus, disc_.cell_material(cp));
    if (minus) return boundary_star(l, f, *minus, disc_.cell_material(cm), 1, t);
    return boundary_star(l, f, *plus, disc_.cell_material(cp), 0, t);
  }

  const Grid<dim>& grid_;
  const Disc& disc_;
  FluxScheme scheme_;
  Eigen::Matrix<double, dim, 1> face_weight_;
  FaceTopology<dim> faces_;
  BoundaryFaces<dim> boundary_;
  // CTU only: star states of the faces of each axis and the fluctuations entering their sides
  // (column 2 f: into the minus cell, 2 f + 1: into the plus cell).
  mutable std::array<NodalField, dim> star_;
  mutable FaceFluctuations fluctuation_;
  // Fused stages: each thread's upper-face star states.
  mutable std::vector<State> star_cache_;
};

}  // namespace dgmpm
