#pragma once
// Everything the DGMPM operators need from one particle configuration: which particles each cell
// holds, their local coordinates (shape values and pseudo-stiffness matrices follow from them),
// lumped nodal masses and cell materials (docs/method.md, "Discretisation"). Built once for fixed
// particles, rebuilt after every move otherwise.
//
// Cells whose particles sit exactly where those of one reference cell sit, with the same masses
// and material (every full cell of a regular lattice), share its layout: their shape values,
// gradients and pseudo-stiffness are computed once per build, from the reference cell, by the
// code that computes any other cell's: the same values to the last bit. A shared cell whose face
// neighbours all share it too, at the next and previous index along each axis (no periodic wrap),
// is interior: the operators step it without looking up its faces, their boundaries, its
// neighbours' materials or massless nodes (dg_operator.hpp).

#include "grid.hpp"
#include "particles.hpp"
#include "shape_functions.hpp"
#include "thread_share.hpp"

#include <Eigen/Core>
#include <algorithm>
#include <array>
#include <atomic>
#include <cstring>
#ifdef _OPENMP
#include <omp.h>
#endif
#include <sstream>
#include <stdexcept>
#include <vector>

namespace dgmpm {

struct ParticleOutsideGrid : std::runtime_error {
  int particle;
  ParticleOutsideGrid(int p, const std::string& what) : std::runtime_error(what), particle(p) {}
};

// Throws ParticleOutsideGrid for particle p, naming it and its position.
template <int Dim, int NComp, int NInternal>
[[noreturn]] void throw_outside_grid(const Particles<Dim, NComp, NInternal>& particles, int p) {
  std::ostringstream s;
  s << "particle " << particles.id[p] << " at x = " << particles.position.col(p).transpose()
    << " is outside the grid";
  throw ParticleOutsideGrid(particles.id[p], s.str());
}

// The formulation of the scheme (docs/method.md, "Discretisation"). `paper`: the founding paper's,
// the volume term's pseudo-stiffness K^l_ij = sum_p m_p dS_i/dx_l(x_p) S_j(x_p) and RK2's stages on
// the nodes as they are. `consistent` (the default) departs from it in two places, both where the
// paper's form is unstable at every time step as particles move:
//  - in a cell whose K does not preserve constant states (part-full or over-full cells, and in 2D
//    particles whose mass is not centred along an axis), K^l gains the rank-one term
//    (t^l - K^l 1) u^T, t^l the exact rho int dS_i/dx_l dV and u the nodes' shares of the cell's
//    mass: constant states are preserved at every node and momentum is still conserved (the
//    columns still sum to zero);
//  - RK2's second stage evaluates its residual at a damped first-stage state at nodes holding
//    less than stage_share of their cell's mass (DGOperator::project_and_advance).
// Cells and nodes the paper's form handles well (full cells with centred mass, nodes holding a
// fair share) are left as they are, to the last bit.
enum class Formulation { consistent, paper };

inline const char* to_string(Formulation f) {
  return f == Formulation::consistent ? "consistent" : "paper";
}

template <class Physics>
class Discretisation {
 public:
  static constexpr int dim = Physics::dim;
  static constexpr int npc = 1 << dim;  // nodes per cell
  static constexpr int ncomp = Physics::n_comp;
  using Material = typename Physics::Material;
  using Shape = CellShape<dim>;
  using Stiffness = Eigen::Matrix<double, npc, npc>;
  static constexpr double massless_share = 1e-10;
  // Under the consistent formulation a node holding less than this share of its cell's mass
  // (and more than massless_share) is near-empty: RK2's second stage evaluates its residual there
  // at a damped first-stage state (dg_operator.hpp, project_and_advance). Below the share of a
  // cell's centred particle (1/4 in 2D, 1/2 in 1D), so regular layouts are never damped.
  static constexpr double stage_share = 0.2;
  // Builds of this many cells or particles or more run on threads: the particles' cells, the sort
  // by cell, then the cells' values (each cell writes only its own); the blends of mixed cells (in
  // cell order) stay serial. The result does not depend on the number of threads.
  static constexpr int kThreaded = 4096;
  static constexpr double overfull_tolerance = 1e-6;  // a fill above 1 + this is over-full

  // A cell whose particles carry m_c != rho V (moving particles piling up, a body ending inside
  // the cell), or in 2D whose particles' mass is not centred along an axis, has a paper's volume
  // term that does not cancel its face fluxes on a constant state (tests/lib_consistency.cpp).
  // Its RK2 stage values then drift at nodes holding little mass, by the residual over that mass:
  // the cause of the blow-ups of moving particles near faces and of the weak long-wave growth of
  // off-centre particles under RK2 (docs/method.md, "Stability"). The consistent form removes it.
  void set_formulation(Formulation f) { formulation_ = f; }
  Formulation formulation() const { return formulation_; }

  // Rebuilds from the particles' current positions. Storage is reused: no allocation once the
  // sizes are reached. Incremental: when no particle changed cell since the last build (moving
  // particles travel less than a cell per step), the cells keep their particle lists and only
  // the values are recomputed. Throws ParticleOutsideGrid.
  void build(const Grid<dim>& grid, const ParticlesOf<Physics>& particles,
             const std::vector<Material>& materials) {
    const int nc = grid.num_cells(), np = particles.size();
    const bool threaded = std::max(nc, np) >= kThreaded;
    bool same_cells = static_cast<int>(particle_cell_.size()) == np &&
                      static_cast<int>(cell_begin_.size()) == nc + 1;
    particle_cell_.resize(np);
    local_.resize(dim, np);
    int outside = np;  // the first particle outside the grid
#pragma omp parallel for reduction(min : outside) reduction(&& : same_cells) if (threaded)
    for (int p = 0; p < np; ++p) {
      Eigen::Matrix<double, dim, 1> xi;
      const int c = grid.locate(particles.position.col(p), xi);
      if (c < 0) {
        outside = std::min(outside, p);
        continue;
      }
      same_cells = same_cells && particle_cell_[p] == c;
      particle_cell_[p] = c;
      local_.col(p) = xi;
    }
    if (outside < np) throw_outside_grid(particles, outside);
    if (!same_cells) {  // counting sort of the particles by cell
      ++sorts_;
      entries_.resize(np);
      int team = 1;
#ifdef _OPENMP
      if (threaded) team = omp_get_max_threads();
#endif
      if (team > 1) {
        sort_on_threads(nc, np, team);
      } else {
        // Ends of the cells' ranges, then filled from the back: each end moves down to its begin
        // (no scratch array), particles in increasing order within a cell.
        cell_begin_.assign(nc + 1, 0);
        for (int p = 0; p < np; ++p) ++cell_begin_[particle_cell_[p] + 1];
        for (int c = 0; c < nc; ++c) cell_begin_[c + 1] += cell_begin_[c];
        for (int p = np - 1; p >= 0; --p) entries_[--cell_begin_[particle_cell_[p] + 1]] = p;
        for (int c = 0; c < nc; ++c) cell_begin_[c] = cell_begin_[c + 1];
        cell_begin_[nc] = np;
      }
    }

    occupied_.assign(nc, 0);
    match_layouts(particles, threaded);
    // Set cell by cell below, on the threads, rather than by serial fills over every node.
    node_mass_.resize(grid.num_nodes());
    inv_mass_.resize(grid.num_nodes());
    source_corner_.resize(grid.num_nodes());
    cell_size_ = grid.cell_size;
    inverse_cell_size_ = grid.cell_size.cwiseInverse();
    cell_material_.resize(nc);
    table_.assign(materials.begin(), materials.end());  // this build's blends follow
    cell_volume_ = grid.cell_volume();

    int first_overfull = nc;
    bool massless = false, near_empty = false;
#pragma omp parallel for reduction(min                                                             \
                                   : first_overfull)                                               \
    reduction(||                                                                                   \
              : massless, near_empty) if (threaded)
    for (int c = 0; c < nc; ++c) {
      node_mass_.segment<npc>(c * npc).setZero();
      inv_mass_.segment<npc>(c * npc).setZero();
      for (int a = 0; a < npc; ++a) source_corner_[c * npc + a] = -1;
      double cell_mass = 0.0;
      int pure = -1;  // the material every particle so far carries; kMixed once several
      for (int e = cell_begin_[c]; e < cell_begin_[c + 1]; ++e) {
        const int p = entries_[e];
        const double m = particles.mass[p];
        node_mass_.segment<npc>(c * npc) += m * Shape::values(local_.col(p));
        const int k = particles.material[p];
        if (cell_mass == 0.0) pure = k;
        if (k != pure) pure = kMixed;
        cell_mass += m;
      }
      occupied_[c] = cell_mass <= 0.0                             ? 0
                     : occupied_[c] == kShared && layout_sharing_ ? kShared
                                                                  : kOccupied;
      if (!occupied_[c]) continue;
      massless = set_node_sources(c, cell_mass) || massless;
      for (int a = 0; a < npc; ++a) {
        const double m = node_mass_[c * npc + a];
        if (formulation_ == Formulation::consistent && m > massless_share * cell_mass &&
            m < stage_share * cell_mass)
          occupied_[c] |= kNearEmpty;
      }
      near_empty = near_empty || (occupied_[c] & kNearEmpty);
      cell_material_[c] = pure;
      if (pure != kMixed) finish_cell(c, first_overfull);
    }
    // Mixed cells, in cell order: their blends join the table.
    for (int c = 0; c < nc; ++c) {
      if (!occupied_[c] || cell_material_[c] != kMixed) continue;
      double cell_mass = 0.0;
      int pure = -1;     // as above, until mixed
      Material blended;  // the mass-weighted blend once mixed
      for (int e = cell_begin_[c]; e < cell_begin_[c + 1]; ++e) {
        const int p = entries_[e];
        const double m = particles.mass[p];
        const int k = particles.material[p];
        if (cell_mass == 0.0) {
          pure = k;
        } else if (pure < 0 || k != pure) {
          blended =
              Physics::blend(pure >= 0 ? materials[pure] : blended, cell_mass, materials[k], m);
          pure = -1;
        }
        cell_mass += m;
      }
      cell_material_[c] = static_cast<int>(table_.size());
      table_.push_back(blended);
      finish_cell(c, first_overfull);
    }
    has_massless_ = massless;
    has_near_empty_ = near_empty;
    first_overfull_ = first_overfull < nc ? first_overfull : -1;
    exact_row_sum_.resize(table_.size());
    for (std::size_t k = 0; k < table_.size(); ++k)
      for (int l = 0; l < dim; ++l)
        exact_row_sum_[k][l] =
            Physics::density(table_[k]) * cell_volume_ / (cell_size_[l] * (npc / 2));
    shared_layout_values(particles.mass);
    mark_interior(grid);
  }

  int num_cells() const {
    return static_cast<int>(occupied_.size());
  }
  int cell_begin(int c) const {
    return cell_begin_[c];
  }
  int cell_end(int c) const {
    return cell_begin_[c + 1];
  }
  int entry_particle(int e) const {
    return entries_[e];
  }
  // Shape values of entry e's particle at its cell's nodes: computed from its local coordinates
  // when asked (a few products; storing them cost npc doubles per particle).
  typename Shape::Values entry_shape(int e) const {
    return Shape::values(local_.col(entries_[e]));
  }
  auto particle_local(int p) const {
    return local_.col(p);
  }
  bool occupied(int c) const {
    return occupied_[c] != 0;
  }
  // Whether occupied cell c has the shared layout (see above).
  bool shares_layout(int c) const {
    return occupied_[c] >= kShared;
  }
  // Whether cell c is interior (see above): it shares the layout, has no massless node, and so do
  // its face neighbours c +- stride_l, which are its neighbours across the grid.
  bool interior(int c) const {
    return occupied_[c] >= kInterior;
  }
  // Shape values of the shared layout's particle j (entry order within a cell that shares it).
  const typename Shape::Values& shared_shape(int j) const {
    return shared_.shape[j];
  }
  // Cells with the shared layout (0 when no two cells share one).
  int shared_cells() const {
    return shared_cells_;
  }
  // Whether the layout is shared (on by default); off, every cell computes its own values (the
  // results are the same to the last bit: tests/solver_shared_layout.cpp).
  void set_layout_sharing(bool on) {
    layout_sharing_ = on;
  }
  // The material of cell c's particles, mass-weighted when they carry several.
  const Material& cell_material(int c) const {
    return table_[cell_material_[c]];
  }
  // Cell c's pseudo-stiffness matrices, one per axis: K^l = sum_p m_p grad_l S(x_p) S(x_p)^T
  // (made consistent where it is not: set_formulation), `mass` the masses of the particles
  // built from. Computed when asked from the cell's particles: a few products per particle, where
  // storing them cost npc^2 doubles per cell and axis (256 bytes per cell in 2D).
  std::array<Stiffness, dim> stiffness(int c, const Eigen::VectorXd& mass) const {
    if (shares_layout(c)) return shared_.stiffness;
    std::array<Stiffness, dim> k;
    for (auto& kl : k) kl.setZero();
    typename Shape::Values share;
    const double cell = visit_shapes(c, mass, share, [&](double m, const auto& s, const auto& g) {
      for (int l = 0; l < dim; ++l) k[l] += m * g.row(l).transpose() * s.transpose();
    });
    if (formulation_ == Formulation::consistent && cell > 0.0) make_consistent(c, share / cell, k);
    return k;
  }
  // The shared layout's K^l (only for a cell that shares_layout).
  const std::array<Stiffness, dim>& shared_stiffness() const {
    return shared_.stiffness;
  }
  // rc += sum_l F_l K^l^T (F_l: npc columns of fluxes along l) without forming K^l: the sum over
  // the cell's particles of m_p (F_l S_p) (grad_l S_p)^T, plus the consistency correction
  // (F_l u) d_l^T of make_consistent. Fewer operations than stiffness() and the products for a
  // single particle in 2D (rank_one_cheaper); equal to them to round-off. `fluxes_times(w)`
  // returns F_l w for every l, w a vector of npc weights (a physics whose flux is linear takes it
  // as the flux of the state q w, not from the fluxes of the nodes: physics::LinearFlux).
  template <class FluxesTimes, class Out>
  void add_stiffness_products(int c, const Eigen::VectorXd& mass, const FluxesTimes& fluxes_times,
                              Out& rc) const {
    if (shares_layout(c)) {  // the sums below with the shared layout's values and defects
      for (int j = 0; j < shared_.count; ++j) {
        const auto at = fluxes_times(shared_.shape[j]);
        for (int l = 0; l < dim; ++l)
          rc.noalias() += (shared_.mass[j] * at[l]) * shared_.gradient[j].row(l);
      }
      if (std::any_of(shared_.defective.begin(), shared_.defective.end(),
                      [](bool b) { return b; })) {
        const auto at = fluxes_times(shared_.mass_share);
        for (int l = 0; l < dim; ++l)
          if (shared_.defective[l]) rc.noalias() += at[l] * shared_.defect[l].transpose();
      }
      return;
    }
    std::array<typename Shape::Values, dim> row_sums;  // K^l 1
    for (auto& r : row_sums) r.setZero();
    typename Shape::Values share;
    const double cell = visit_shapes(c, mass, share, [&](double m, const auto& s, const auto& g) {
      const double sum = s.sum();
      const auto at = fluxes_times(s);
      for (int l = 0; l < dim; ++l) {
        rc.noalias() += (m * at[l]) * g.row(l);
        row_sums[l] += (m * sum) * g.row(l).transpose();
      }
    });
    if (formulation_ != Formulation::consistent || cell <= 0.0) return;
    const typename Shape::Values u = share / cell;
    std::array<typename Shape::Values, dim> d;
    std::array<bool, dim> defective;
    for (int l = 0; l < dim; ++l) defective[l] = consistency_defect(c, l, row_sums[l], d[l]);
    if (std::none_of(defective.begin(), defective.end(), [](bool b) { return b; })) return;
    const auto at = fluxes_times(u);
    for (int l = 0; l < dim; ++l)
      if (defective[l]) rc.noalias() += at[l] * d[l].transpose();
  }
  // f(m_p, S(x_p), grad S(x_p)) for each particle p of cell c, in order; returns the cell's mass
  // and sets `share` to sum_p m_p S(x_p).
  // (Forced inline: left to the compiler, the 2D step at one particle per cell executed 8% more
  // instructions.)
  template <class F>
  [[gnu::always_inline]] inline double visit_shapes(int c, const Eigen::VectorXd& mass,
                                                    typename Shape::Values& share, F&& f) const {
    share.setZero();
    double cell = 0.0;
    for (int e = cell_begin_[c]; e < cell_begin_[c + 1]; ++e) {
      const int p = entries_[e];
      const auto s = Shape::values(local_.col(p));
      f(mass[p], s, Shape::gradients(local_.col(p), inverse_cell_size_));
      share += mass[p] * s;
      cell += mass[p];
    }
    return cell;
  }
  // Whether the K^l products are taken without forming K^l (add_stiffness_products) for a cell
  // of n particles: a single particle in 2D and 3D, where dim 2 ncomp npc multiply-adds are fewer
  // than dim npc^2 + dim ncomp npc^2 for any ncomp (callgrind, bench/count_flops.py: 2D DCU
  // Euler at one particle per cell, 2421 -> 2127 instructions per particle-step). Not in 1D,
  // where the matrices are 2 x 2 and the sums executed more instructions (558 -> 580). Not for
  // two or three particles either, though the count favours them in plane strain: there the
  // sums' round-off moved the admissible Courant number of a two-particle layout by 3e-5 (a
  // limit set by a marginal long-wave mode; tests/stability_two_dimensions.cpp).
  static constexpr bool rank_one_cheaper(int n) {
    return dim > 1 && n == 1;
  }
  double node_mass(int i) const {
    return node_mass_[i];
  }
  // Mass of cell c's particles over rho V (rho their material's density): 1 for a full cell.
  double fill(int c) const {
    return cell_mass(c) / (Physics::density(cell_material(c)) * cell_volume_);
  }
  // Mass of cell c's particles (the sum of its lumped nodal masses).
  double cell_mass(int c) const {
    return node_mass_.template segment<npc>(c * npc).sum();
  }
  double inverse_mass(int i) const {
    return inv_mass_[i];
  }
  // i itself for a node with mass; for a massless node of an occupied cell, the node of the same
  // cell that stands in for it; -1 for the nodes of a void cell.
  int node_source(int i) const {
    const int a = source_corner_[i];
    return a < 0 ? -1 : i - i % npc + a;
  }
  // The same as a corner of node i's cell (0 to npc - 1), or -1: one byte per node.
  int source_corner(int i) const {
    return source_corner_[i];
  }
  // Whether some occupied cell has a massless node (whose residual the update folds into a
  // node of the same cell that has mass: node_source).
  bool has_massless_nodes() const {
    return has_massless_;
  }
  // Whether some occupied cell, or cell c, has a near-empty node (stage_share).
  bool has_near_empty_nodes() const {
    return has_near_empty_;
  }
  bool near_empty(int c) const {
    return occupied_[c] & kNearEmpty;
  }
  int num_particles() const {
    return static_cast<int>(entries_.size());
  }
  // Whether occupied cell c's fill exceeds 1 + overfull_tolerance.
  bool overfull(int c) const {
    return fill(c) > 1.0 + overfull_tolerance;
  }
  // The first cell (by index) whose fill exceeds 1 + overfull_tolerance, or -1: found by the
  // build, so that no pass over the cells looks for it.
  int first_overfull_cell() const {
    return first_overfull_;
  }
  // Builds that had to sort the particles by cell (the others kept the cells' particle lists).
  long sorts() const {
    return sorts_;
  }

 private:
  // The counting sort on up to `team` threads: each counts its contiguous range of particles per
  // cell; within each cell the threads' ranges follow each other in thread order; each thread
  // places its particles in order. The serial sort's order: increasing within a cell.
  void sort_on_threads(int nc, int np, int team) {
    cell_begin_.resize(nc + 1);
    sort_counts_.assign(static_cast<std::size_t>(team) * nc, 0);
    sort_blocks_.assign(team + 1, 0);
#pragma omp parallel num_threads(team)
    {
      const TeamPlace place = team_place();
      const int t = place.thread, n = place.team;
      const auto count = [&](int u, int c) -> int& {
        return sort_counts_[static_cast<std::size_t>(u) * nc + c];
      };
      const Share particles = thread_share(np, place), cells = thread_share(nc, place);
      for (int p = particles.begin; p < particles.end; ++p) ++count(t, particle_cell_[p]);
#pragma omp barrier
      int total = 0;  // the particles of this thread's cells
      for (int c = cells.begin; c < cells.end; ++c)
        for (int u = 0; u < n; ++u) total += count(u, c);
      sort_blocks_[t + 1] = total;
#pragma omp barrier
#pragma omp single
      for (int u = 0; u < n; ++u) sort_blocks_[u + 1] += sort_blocks_[u];
      int next = sort_blocks_[t];  // counts become each thread's first place in each cell
      for (int c = cells.begin; c < cells.end; ++c) {
        cell_begin_[c] = next;
        for (int u = 0; u < n; ++u) {
          const int here = count(u, c);
          count(u, c) = next;
          next += here;
        }
      }
#pragma omp barrier
      for (int p = particles.begin; p < particles.end; ++p)
        entries_[count(t, particle_cell_[p])++] = p;
    }
    cell_begin_[nc] = np;
  }

  // A massless node (every particle of its cell on the far side) takes no part in the update.
  // Its value is that of the nearest node with mass in the same cell and its residual is added
  // to that node: for Euler the limit of a vanishing nodal mass; conservative in any case. A node
  // holding less than `massless_share` of its cell's mass counts as massless: dividing by it
  // would amplify round-off by the inverse of that share.
  // Returns whether the cell has a massless node.
  bool set_node_sources(int c, double cell_mass) {
    bool massless = false;
    for (int a = 0; a < npc; ++a) {
      const int i = c * npc + a;
      if (node_mass_[i] > massless_share * cell_mass) {
        inv_mass_[i] = 1.0 / node_mass_[i];
        source_corner_[i] = static_cast<signed char>(a);
      }
    }
    for (int a = 0; a < npc; ++a) {
      const int i = c * npc + a;
      if (source_corner_[i] >= 0) continue;
      int best = -1, best_distance = dim + 1;
      for (int b = 0; b < npc; ++b) {
        const int d = __builtin_popcount(static_cast<unsigned>(a ^ b));
        if (inv_mass_[c * npc + b] > 0.0 && d < best_distance) best = b, best_distance = d;
      }
      source_corner_[i] = static_cast<signed char>(best);
      massless = true;
    }
    return massless;
  }

  // Finds the cells whose particles sit as those of a reference cell sit: the same count,
  // material, masses and local coordinates to the last bit, so that sharing changes no result
  // and which cell is the reference (a rank of a distributed run picks its own) changes only the
  // speed. Marks them kShared in occupied_. The reference is the sampled cell whose layout most
  // other samples have: positions computed as (i + f) h put x / h - i at f in most cells but a
  // few last bits off it in others (1D, h = 1 / 4000, one particle per cell: 1.2% of the cells).
  // Nothing is shared unless two samples agree.
  void match_layouts(const ParticlesOf<Physics>& particles, bool threaded) {
    const int nc = num_cells();
    shared_.count = 0;
    const auto same_bits = [](const double& a, const double& b) {
      return std::memcmp(&a, &b, sizeof(double)) == 0;  // -0 and +0 differ
    };
    // Whether cells c and r hold one material with the same masses and coordinates, in order.
    const auto same_layout = [&](int c, int r) {
      const int n = cell_end(r) - cell_begin(r);
      if (cell_end(c) - cell_begin(c) != n) return false;
      const int material = particles.material[entries_[cell_begin(r)]];
      for (int j = 0; j < n; ++j) {
        const int p = entries_[cell_begin(c) + j], q = entries_[cell_begin(r) + j];
        if (particles.material[p] != material || particles.material[q] != material ||
            !same_bits(particles.mass[p], particles.mass[q]))
          return false;
        for (int l = 0; l < dim; ++l)
          if (!same_bits(local_(l, p), local_(l, q))) return false;
      }
      return true;
    };
    std::array<int, kLayoutSamples> sample;
    int samples = 0;
    for (int k = 0; k < kLayoutSamples; ++k) {
      int c = static_cast<int>(static_cast<long long>(nc) * k / kLayoutSamples);
      while (c < nc && cell_end(c) == cell_begin(c)) ++c;
      if (c < nc && (samples == 0 || sample[samples - 1] != c)) sample[samples++] = c;
    }
    int reference = -1, most = 0;
    for (int i = 0; i < samples; ++i) {
      int agree = 0;
      for (int j = 0; j < samples; ++j) agree += same_layout(sample[j], sample[i]);
      if (agree > most) most = agree, reference = sample[i];
    }
    // A layout no two samples have is rare across the grid (moving particles): scanning every
    // cell for it would cost more than sharing it saves.
    if (most < 2) return;
    if (!same_layout(reference, reference)) return;  // mixed materials
    const int n = cell_end(reference) - cell_begin(reference);
    shared_.mass.resize(n);
    shared_.local.resize(dim, n);
    for (int j = 0; j < n; ++j) {
      const int p = entries_[cell_begin(reference) + j];
      shared_.mass[j] = particles.mass[p];
      shared_.local.col(j) = local_.col(p);
    }
    shared_.reference = reference;
    shared_.count = n;
    const int material = particles.material[entries_[cell_begin(reference)]];
    // The scan compares against the copy, coordinates first: they tell most cells apart.
    const auto matches = [&](int c) {
      if (cell_end(c) - cell_begin(c) != n) return false;
      for (int j = 0; j < n; ++j) {
        const int p = entries_[cell_begin(c) + j];
        for (int l = 0; l < dim; ++l)
          if (!same_bits(local_(l, p), shared_.local(l, j))) return false;
        if (!same_bits(particles.mass[p], shared_.mass[j]) || particles.material[p] != material)
          return false;
      }
      return true;
    };
#pragma omp parallel for if (threaded)
    for (int c = 0; c < nc; ++c)
      if (matches(c)) occupied_[c] = kShared;
  }
  static constexpr int kLayoutSamples = 9;  // cells sampled for the reference, across the grid

  // The shared layout's values, from the reference cell (its material set), and the count of the
  // cells that share it.
  void shared_layout_values(const Eigen::VectorXd& mass) {
    const int nc = num_cells();
    shared_cells_ = 0;
    if (!layout_sharing_ || shared_.count == 0) return;
    const int reference = shared_.reference, n = shared_.count;
    if (kind(occupied_[reference]) != kShared) {  // no mass: nothing to share
      for (int c = 0; c < nc; ++c)
        if (occupied_[c]) set_kind(c, kOccupied);
      return;
    }
    for (int c = 0; c < nc; ++c) shared_cells_ += kind(occupied_[c]) == kShared;
    shared_.shape.resize(n);
    shared_.gradient.resize(n);
    for (int j = 0; j < n; ++j) {
      shared_.shape[j] = Shape::values(shared_.local.col(j));
      shared_.gradient[j] = Shape::gradients(shared_.local.col(j), inverse_cell_size_);
    }
    // Computed while the reference is not yet marked shared: the code any other cell runs.
    set_kind(reference, kOccupied);
    shared_.stiffness = stiffness(reference, mass);
    // add_stiffness_products' consistency part, from the reference's row sums.
    std::array<typename Shape::Values, dim> row_sums;
    for (auto& r : row_sums) r.setZero();
    typename Shape::Values share;
    const double cell =
        visit_shapes(reference, mass, share, [&](double m, const auto& s, const auto& g) {
          const double sum = s.sum();
          for (int l = 0; l < dim; ++l) row_sums[l] += (m * sum) * g.row(l).transpose();
        });
    shared_.mass_share = share / cell;
    for (int l = 0; l < dim; ++l)
      shared_.defective[l] = formulation_ == Formulation::consistent && cell > 0.0 &&
                             consistency_defect(reference, l, row_sums[l], shared_.defect[l]);
    set_kind(reference, kShared);
  }

  // Marks the interior cells: shared, with shared face neighbours at c +- stride_l. A layout with a
  // massless node has none (its cells fold residuals between nodes).
  void mark_interior(const Grid<dim>& grid) {
    if (shared_cells_ == 0) return;
    for (int a = 0; a < npc; ++a)
      if (source_corner_[shared_.reference * npc + a] != a) return;
    const int nc = num_cells();
    std::array<int, dim> stride;
    for (int l = 0, s = 1; l < dim; s *= grid.cells[l], ++l) stride[l] = s;
    // Row by row along the first axis: a row's place along the others is found once (1D: one
    // row, serial). Relaxed atomics: a thread reads neighbours that another marks (kShared ->
    // kInterior, both shared).
    const auto shared = [&](int c) {
      return std::atomic_ref<char>(occupied_[c]).load(std::memory_order_relaxed) >= kShared;
    };
    const int row = grid.cells[0], rows = nc / row;
#pragma omp parallel for if (nc >= kThreaded)
    for (int r = 0; r < rows; ++r) {
      bool inner_row = true;
      for (int l = 1, rest = r; l < dim; rest /= grid.cells[l], ++l)
        inner_row =
            inner_row && rest % grid.cells[l] > 0 && rest % grid.cells[l] + 1 < grid.cells[l];
      if (!inner_row) continue;
      for (int c = r * row + 1; c < (r + 1) * row - 1; ++c) {
        const char state = occupied_[c];  // only this thread writes it
        if (kind(state) != kShared) continue;
        bool inside = true;
        for (int l = 0; l < dim && inside; ++l)
          inside = shared(c - stride[l]) && shared(c + stride[l]);
        if (inside)
          std::atomic_ref<char>(occupied_[c])
              .store(static_cast<char>((state & kNearEmpty) | kInterior),
                     std::memory_order_relaxed);
      }
    }
  }

  // The over-full check of an occupied cell whose material is set.
  void finish_cell(int c, int& first_overfull) const {
    if (overfull(c)) first_overfull = std::min(first_overfull, c);
  }

  // K^l += (t^l - K^l 1) u^T where the rows of K^l do not sum to t^l, the exact
  // rho int dS_i/dx_l dV = +-rho V / (h_l 2^(dim - 1)) (the sign of node i's side along l); u the
  // nodes' shares of the cell's mass. Cells that preserve constant states already (full 1D cells,
  // layouts centred along each axis) are left as they are, to the last bit.
  void make_consistent(int c, const typename Shape::Values& share,
                       std::array<Stiffness, dim>& k) const {
    for (int l = 0; l < dim; ++l) {
      typename Shape::Values defect;
      if (consistency_defect(c, l, k[l].rowwise().sum(), defect))
        k[l].noalias() += defect * share.transpose();
    }
  }
  // t^l - K^l 1 from the row sums of K^l, and whether it exceeds round-off.
  bool consistency_defect(int c, int l, const typename Shape::Values& row_sums,
                          typename Shape::Values& defect) const {
    const double exact = exact_row_sum_[cell_material_[c]][l];
    for (int a = 0; a < npc; ++a) defect[a] = (((a >> l) & 1) ? exact : -exact);
    defect -= row_sums;
    return defect.cwiseAbs().maxCoeff() > kConsistentTolerance * exact;
  }
  // Relative row-sum defect below which a cell counts as consistent (round-off of the sums).
  static constexpr double kConsistentTolerance = 1e-12;

  static constexpr int kMixed = -2;  // cell_material_ of a mixed cell before its blend
  // occupied_: a cell's kind (0 empty, kOccupied, kShared, kInterior, each including the ones
  // before it) plus the flag kNearEmpty, which only RK2 reads: one byte per cell for both, and
  // the sweep's tests of kind stay one comparison.
  static constexpr char kNearEmpty = 1;  // some node holds a (massless, stage) share of the mass
  static constexpr char kOccupied = 2;
  static constexpr char kShared = 4;    // ... with the shared layout
  static constexpr char kInterior = 6;  // ... and interior
  static char kind(char state) {
    return state & ~kNearEmpty;
  }
  void set_kind(int c, char k) {
    occupied_[c] = static_cast<char>((occupied_[c] & kNearEmpty) | k);
  }

  // The shared layout: its particles (entry order) and what the cells that share it read.
  struct SharedLayout {
    int count = 0;  // particles (0: no layout shared)
    int reference = -1;
    std::vector<double> mass;
    Eigen::Matrix<double, dim, Eigen::Dynamic> local;
    std::vector<typename Shape::Values> shape;
    std::vector<typename Shape::Gradients> gradient;
    std::array<Stiffness, dim> stiffness;
    typename Shape::Values mass_share;  // u of make_consistent
    std::array<bool, dim> defective{};
    std::array<typename Shape::Values, dim> defect;
  };
  SharedLayout shared_;
  int shared_cells_ = 0;
  bool layout_sharing_ = true;
  std::vector<Eigen::Matrix<double, dim, 1>> exact_row_sum_;  // per table_ entry, per axis

  std::vector<int> particle_cell_;
  Eigen::Matrix<double, dim, Eigen::Dynamic> local_;
  std::vector<int> cell_begin_, entries_;
  std::vector<int> sort_counts_, sort_blocks_;  // sort_on_threads' counts: per thread, per cell
  Eigen::VectorXd node_mass_, inv_mass_;
  std::vector<signed char> source_corner_;
  typename Grid<dim>::Vec cell_size_ = Grid<dim>::Vec::Ones();
  typename Grid<dim>::Vec inverse_cell_size_ = Grid<dim>::Vec::Ones();
  std::vector<Material> table_;     // the scene's materials, then the blends of mixed cells
  std::vector<int> cell_material_;  // index into table_
  std::vector<char> occupied_;      // per cell: its kind and flag (kOccupied above)
  bool has_massless_ = false, has_near_empty_ = false;
  Formulation formulation_ = Formulation::consistent;
  double cell_volume_ = 0.0;
  int first_overfull_ = -1;
  long sorts_ = 0;
};

}  // namespace dgmpm
