#pragma once
// Time step control: dt = C h / c from a fixed Courant number, or, with "courant": "auto",
// dt = S min over occupied cells of min(1, f) C*(layout) h / c_cell, C* being the admissible
// Courant number of the cell's particle layout from stability/ (the analysis of the operators the
// solver runs) and f the cell's fill: its particles' mass over rho times its volume. h is the
// smallest cell size, c the largest wave speed of the cell's material. C* follows the scene's
// criterion: the growth budget (the default: the L2 limit, or above it, when the layout is weakly
// unstable, the largest C at which no mode grows by more than time.growth_budget over the run),
// the strict L2 criterion, or the monotone one (1D).
//
// The fill factor is the small-cell rule: a partly filled cell (a body ending inside it) has
// nodal masses f times those of the full layout the analysis assumes, while the face fluxes are
// unchanged, so waves cross it as if it were f h long. The periodic model cannot see this (every
// cell is full there); tests/solver_time_step.cpp checks the rule against the spectral radius of
// the whole scene's operator.
//
// Layouts are analysed once and cached. Fixed particles' layouts are keyed to 1e-9. Moving
// particles' positions drift every step, so a cell's C* is bounded from a lattice instead: the
// smallest C* over the corners of the lattice box that holds the layout, corners analysed once
// each. Layouts of up to four coordinates take a lattice of positions (LayoutLattice); larger
// ones a lattice of their mass moments (per axis mean and spread) when they are products of
// per-axis positions or close to one; others are rounded to 1/4096 (LayoutQuantisation). The
// paper's formulation keeps the rounding for all: there C* -> 0 as a particle closes on a node
// (and jumps back to 1 on it), which no lattice box bounds usefully.

#include "solver/scene.hpp"

#include <dgmpm/discretisation.hpp>
#include <dgmpm/grid.hpp>
#include <dgmpm/physics/contract.hpp>
#include <stability/admissible_courant.hpp>
#include <stability/layout.hpp>
#include <stability/options.hpp>

#include <algorithm>
#include <array>
#include <chrono>
#include <cmath>
#include <cstdint>
#include <exception>
#include <limits>
#include <map>
#include <set>
#include <type_traits>
#include <unordered_map>
#include <utility>
#include <vector>

namespace dgmpm {

// Positions (local coordinates) are rounded before the analysis, so that the cache serves
// layouts equal but for round-off (fixed particles) or drifting slowly (moving particles of
// large layouts): to multiples of a quantum, except near a node, where C* varies like the
// distance d to it: there d keeps 8 significant bits (relative error 2^-9, finer than the quantum
// below 2^8 quanta). Below half a quantum the particle is put on the node: the resolution of the
// cache. Some layouts have C* -> 0 as d -> 0 but C* = 1 at d = 0 ({0, 1 - d}); resolving them
// would let a layout that moving particles pass through in a step or two stall the run
// (dt ~ d h / c). tests/solver_time_step_quantisation.cpp measures the error on both sides of q
// / 2.
struct LayoutQuantisation {
  static constexpr double fixed_position_quantum = 1e-9;
  static constexpr double moving_position_quantum = 1.0 / 4096;
  static constexpr int node_distance_bits = 8;
  // The rounded local position: onto the node if d = min(xi, 1 - xi) < quantum / 2, else moved
  // by at most min(quantum / 2, d 2^-9).
  static double quantise_position(double xi, double quantum);
};

// The lattice of local positions a moving particle's C* is bounded from: uniform with spacing
// 1/Uniform where the distance d to the nearest node is at least 1/16, and geometric below,
// PerOctave points per halving of d, down to 2^-13, then the node. Near a node C* varies like d
// (two particles closing on a face from both sides) or faster: the geometric points keep a box's
// relative width constant, and the box's smaller distance is one of its corners. 1D analyses are
// cheap (a fine lattice: 1/64, four per octave, 131 points); a 2D one costs 10-50 ms, and moving
// particles would visit thousands of fine corners: 1/16 and one per octave there (35 points).
template <int PerOctave, int Uniform>
struct LayoutLattice {
  static constexpr int kPerOctave = PerOctave, kOctaves = 9, kUniform = Uniform;
  static constexpr int kNear = kPerOctave * kOctaves;  // geometric points per node
  static constexpr int kSide = 1 + kNear + kUniform / 2 - kUniform / 16 + 1;  // 0 .. 1/2
  static constexpr int kPoints = 2 * kSide - 1;                               // 0 .. 1, 1/2 once
  static_assert(kPoints < 256, "a box index is one byte of the cache's code");
  // The lattice's points in increasing order, from 0 to 1.
  static const std::array<double, kPoints>& points() {
    static const std::array<double, kPoints> lattice = [] {
      std::array<double, kPoints> p{};
      int k = 0;
      p[k++] = 0.0;
      for (int j = kNear; j >= 1; --j)
        p[k++] = std::exp2(-4.0 - static_cast<double>(j) / kPerOctave);
      for (int u = kUniform / 16; u <= kUniform / 2; ++u)
        p[k++] = static_cast<double>(u) / kUniform;
      for (int m = kSide - 2; m >= 0; --m) p[k++] = 1.0 - p[m];  // the mirror image, 1/2 once
      return p;
    }();
    return lattice;
  }
  // The index of the box [points[k], points[k + 1]] holding xi in [0, 1] (the last box for 1).
  static int box(double xi) {
    constexpr int first_uniform = kNear + 1;  // the index of 1/16
    if (xi >= 1.0 / 16 && xi < 15.0 / 16) {
      const int u = static_cast<int>(xi * kUniform);  // exact: kUniform is a power of 2
      return first_uniform + (u - kUniform / 16);
    }
    const auto& p = points();
    const auto it = std::upper_bound(p.begin(), p.end(), xi);
    return std::clamp(static_cast<int>(it - p.begin()) - 1, 0, kPoints - 2);
  }
};
using FineLayoutLattice = LayoutLattice<4, 64>;
using CoarseLayoutLattice = LayoutLattice<1, 16>;

template <class Physics>
class TimeStepControl : public LayoutQuantisation {
 public:
  static constexpr int dim = Physics::dim;
  using Disc = Discretisation<Physics>;
  using ParticleSet = ParticlesOf<Physics>;
  using Lattice = std::conditional_t<dim == 1, FineLayoutLattice, CoarseLayoutLattice>;

  // `max_wave_speed`: of the materials the particles carry (the growth budget's horizon is the
  // run's length in crossings of the smallest cell at that speed). Throws scene::SceneError for a
  // criterion the analysis cannot apply (2D elastic monotone).
  TimeStepControl(const scene::Scene& scene, double max_wave_speed)
      : automatic_(scene.time.courant_auto), courant_(scene.time.courant),
        safety_(scene.time.safety),
        lattice_(scene.particles_move && scene.formulation == Formulation::consistent),
        quantum_(scene.particles_move ? moving_position_quantum : fixed_position_quantum),
        criterion_(scene.time.criterion) {
    setting_.dim = dim;
    setting_.time = scene.time.integrator;
    setting_.flux = scene.flux;
    setting_.model = stability::Model::elastic;
    setting_.formulation = scene.formulation;
    if (dim > 1) setting_.aspect = scene.grid.cell_size[0] / scene.grid.cell_size[1];
    if (automatic_ && dim > 1 && criterion_ == stability::Criterion::monotone)
      throw scene::SceneError(
          scene.source +
          ": time.criterion: value \"monotone\" is not available in 2D: the elastic system does "
          "not split into the scalar waves the criterion needs; allowed: \"budget\" or \"l2\"");
    budget_.factor = scene.time.growth_budget;
    budget_.crossings = true;
    double h = std::numeric_limits<double>::infinity();
    for (double s : scene.grid.cell_size) h = std::min(h, s);
    budget_.horizon = std::max(1.0, max_wave_speed * scene.time.end / h);
    // A lone particle's map does not depend on where it sits, but for RK2 in 2D (the second
    // stage sees the unequal nodal masses of an off-centre particle).
    lone_particle_shared_ = dim == 1 || setting_.time == TimeScheme::euler;
    // Mirrors (and the swap of x and y in square cells) map a layout to one of the same C*.
    swap_symmetric_ = dim == 2 && setting_.aspect == 1.0;
  }

  bool automatic() const { return automatic_; }
  const stability::GrowthBudget& growth_budget() const { return budget_; }

  // Time step of the current configuration. Fixed Courant: C h / max c over occupied cells. A
  // cell's c: its material's largest speed, or (speeds that change with the state, finite strain)
  // the largest at its particles' current states. NaN when some particle's state is outside the
  // hyperbolic range (no real speed).
  double time_step(const Grid<dim>& grid, const Disc& disc, const ParticleSet& particles,
                   const std::vector<typename Physics::Material>& materials) {
    const auto start = std::chrono::steady_clock::now();
    const double h = grid.cell_size.minCoeff();
    double dt = std::numeric_limits<double>::infinity(), fastest = 0;
    bool hyperbolic = true;
    const int cells = disc.num_cells();
    if (!automatic_) {
#pragma omp parallel for reduction(min : dt) reduction(max : fastest) \
    reduction(&& : hyperbolic) schedule(static) if (physics::StateDependentSpeed<Physics>)
      for (int c = 0; c < cells; ++c) {
        if (!disc.occupied(c)) continue;
        const double speed = cell_speed(disc, particles, materials, c);
        hyperbolic = hyperbolic && speed >= 0;
        fastest = std::max(fastest, speed);
        dt = std::min(dt, courant_ * h / speed);
      }
    } else {
      // Cells whose C* a cache holds (most, once the run has started) on threads; the others,
      // which analyse and fill the caches, after them in cell order.
      if (static_cast<int>(last_code_.size()) != cells) {
        last_code_.assign(cells, 0);
        last_courant_.assign(cells, 0.0);
      }
      misses_.clear();
#pragma omp parallel for reduction(min : dt) reduction(max : fastest) \
    reduction(&& : hyperbolic) schedule(static)
      for (int c = 0; c < cells; ++c) {
        if (!disc.occupied(c)) continue;
        const double speed = cell_speed(disc, particles, materials, c);
        hyperbolic = hyperbolic && speed >= 0;
        fastest = std::max(fastest, speed);
        const double cs = cached_courant(disc, particles, c);
        if (std::isnan(cs)) {
#pragma omp critical(dgmpm_time_step_misses)
          misses_.push_back(c);
          continue;
        }
        dt = std::min(dt, safety_ * std::min(1.0, disc.fill(c)) * cs * h / speed);
      }
      std::sort(misses_.begin(), misses_.end());
      for (const int c : misses_) {
        const double speed = cell_speed(disc, particles, materials, c);
        dt = std::min(dt, safety_ * cell_courant(disc, particles, c) * h / speed);
      }
    }
    fastest_ = fastest;
    selection_seconds_ +=
        std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
    return hyperbolic ? dt : std::numeric_limits<double>::quiet_NaN();
  }

  // Cells the last time_step took on the serial path, no cache holding their C* (automatic
  // steps): 0 once the run's layouts are known.
  int serial_cells() const {
    return static_cast<int>(misses_.size());
  }

  // The largest wave speed the last time_step saw (over this rank's occupied cells).
  double fastest_speed() const {
    return fastest_;
  }

  // The smallest admissible Courant number over the occupied cells, the cell that sets it and
  // its layout (rounded as the cache rounds it).
  struct Limit {
    double courant = 0;  // min(1, fill) C*(layout)
    int cell = -1;
    double fill = 1;
    stability::CellLayout layout;
  };
  Limit smallest_admissible(const Disc& disc, const ParticleSet& particles) {
    Limit limit;
    limit.courant = std::numeric_limits<double>::infinity();
    for (int c = 0; c < disc.num_cells(); ++c) {
      if (!disc.occupied(c)) continue;
      const double cs = cell_courant(disc, particles, c);
      if (cs < limit.courant) limit = {cs, c, disc.fill(c), layout_of(disc, particles, c)};
    }
    return limit;
  }

  // Distinct layouts of the occupied cells that are not analysed yet (what smallest_admissible
  // would analyse for fixed particles), without analysing them.
  int layouts_to_analyse(const Disc& disc, const ParticleSet& particles) {
    std::set<std::vector<double>> keys;
    for (int c = 0; c < disc.num_cells(); ++c) {
      if (!disc.occupied(c) || lone_shared(disc, c)) continue;
      fill_entries(disc, particles, c, quantum_);
      fill_key(disc, c);
      if (!cache_.count(key_)) keys.insert(key_);
    }
    return static_cast<int>(keys.size());
  }

  // The first occupied cell whose layout no lattice bounds (more than kLatticeCoordinates
  // coordinates and not within kTensorTolerance of a tensor product, or every cell under the
  // paper's formulation): analysed at each new rounded layout as its particles drift. -1 when
  // there is none.
  int first_cell_past_the_lattice(const Disc& disc, const ParticleSet& particles) const {
    for (int c = 0; c < disc.num_cells(); ++c) {
      if (!disc.occupied(c)) continue;
      const int n = disc.cell_end(c) - disc.cell_begin(c);
      if (n == 1 && lone_particle_shared_) continue;
      if (!lattice_) return c;
      if (n * dim > kLatticeCoordinates &&
          moments_of(disc, particles, c).non_tensor > kTensorTolerance)
        return c;
    }
    return -1;
  }

  // Distinct layouts analysed so far (cache misses), and the seconds spent analysing them and
  // choosing time steps (analyses included).
  int layouts_analysed() const {
    return static_cast<int>(cache_.size() + corner_cache_.size());
  }
  double analysis_seconds() const {
    return analysis_seconds_;
  }
  double selection_seconds() const {
    return selection_seconds_;
  }

  // The layout of cell c, rounded as for fixed particles or large layouts: positions sorted,
  // masses relative to the first one.
  stability::CellLayout layout_of(const Disc& disc, const ParticleSet& particles, int c) {
    fill_entries(disc, particles, c, quantum_);
    fill_key(disc, c);
    return key_layout();
  }

  // Admissible Courant number of cell c's layout, through the caches (no allocation on a hit),
  // times min(1, fill).
  double cell_courant(const Disc& disc, const ParticleSet& particles, int c) {
    const double small_cell = std::min(1.0, disc.fill(c));
    if (const double cached = cached_courant(disc, particles, c); !std::isnan(cached))
      return small_cell * cached;
    if (lone_shared(disc, c)) {
      fill_entries(disc, particles, c, quantum_);
      lone_courant_.emplace_back(poisson_of(disc, c), analysed(disc, c));
      return small_cell * lone_courant_.back().second;
    }
    const int n = disc.cell_end(c) - disc.cell_begin(c);
    if (lattice_ && n * dim <= kLatticeCoordinates)
      return small_cell * lattice_courant(disc, particles, c);
    if (lattice_)
      if (const double bound = moment_courant(disc, particles, c); !std::isnan(bound))
        return small_cell * bound;
    fill_entries(disc, particles, c, quantum_);
    return small_cell * analysed(disc, c);
  }

  // The largest wave speed in cell c (see time_step).
  static double cell_speed(const Disc& disc, const ParticleSet& particles,
                           const std::vector<typename Physics::Material>& materials, int c) {
    if constexpr (physics::StateDependentSpeed<Physics>) {
      double speed = 0;
      for (int e = disc.cell_begin(c); e < disc.cell_end(c); ++e) {
        const int p = disc.entry_particle(e);
        const double s =
            Physics::state_wave_speed(particles.state.col(p), materials[particles.material[p]]);
        if (std::isnan(s)) return s;
        speed = std::max(speed, s);
      }
      return speed;
    } else {
      (void)particles, (void)materials;
      return Physics::max_wave_speed(disc.cell_material(c));
    }
  }

 private:
  // Layouts of at most this many coordinates are bounded from the lattice (2^4 corners).
  static constexpr int kLatticeCoordinates = 4;

  struct Entry {
    std::array<double, dim> x;
    double mass;
    bool operator<(const Entry& o) const { return x < o.x || (x == o.x && mass < o.mass); }
  };

  bool automatic_;
  double courant_, safety_;
  bool lattice_;
  double quantum_;
  stability::Criterion criterion_;
  stability::AnalysisSetting setting_;
  stability::GrowthBudget budget_;
  bool lone_particle_shared_ = true, swap_symmetric_ = false;
  double analysis_seconds_ = 0, selection_seconds_ = 0;
  double fastest_ = 0;
  // Key: (2D: Poisson's ratio), positions (dim per particle, sorted), then relative masses; the
  // smallest over the layout's mirror images.
  std::map<std::vector<double>, double> cache_;
  // Lattice corners, analysed at a coarser resolution (analyse's `corner`; same keys).
  std::map<std::vector<double>, double> corner_cache_;
  // The one-particle entries, once analysed (when shared): per Poisson ratio (2D).
  std::vector<std::pair<double, double>> lone_courant_;
  std::vector<Entry> entries_, image_;
  std::vector<double> key_, best_key_;
  static constexpr int key_prefix = dim > 1 ? 1 : 0;  // Poisson's ratio in 2D
  // Lattice boxes already bounded: a code of the cell's particle count, lattice boxes, masses
  // (equal, or an index into masses_seen_) and Poisson's ratio (index into poisson_seen_).
  std::unordered_map<std::uint64_t, double> boxes_;
  std::unordered_map<std::uint64_t, double> moment_boxes_;  // moment_code's boxes
  std::vector<std::uint64_t> last_code_;  // per cell: its lone particle's last box code (0: none)
  std::vector<double> last_courant_;      // and that box's C*
  std::vector<std::vector<double>> masses_seen_;
  std::vector<double> poisson_seen_;
  std::vector<double> relative_;
  std::vector<int> misses_;  // time_step: cells no cache held

  static double poisson_of(const Disc& disc, int c) {
    if constexpr (dim == 1)
      return 0.0;
    else
      return disc.cell_material(c).poisson;
  }
  bool lone_shared(const Disc& disc, int c) const {
    return disc.cell_end(c) - disc.cell_begin(c) == 1 && lone_particle_shared_;
  }

  // C* of cell c when a cache holds it, without building a key (the common case once the run has
  // started), else NaN. Reads the caches and writes only cell c's memo: callable from threads.
  double cached_courant(const Disc& disc, const ParticleSet& particles, int c) {
    const int n = disc.cell_end(c) - disc.cell_begin(c);
    if (n == 1 && lone_particle_shared_) {
      const double nu = poisson_of(disc, c);
      for (const auto& [n, courant] : lone_courant_)
        if (n == nu) return courant;
      return kMiss;
    }
    if (!lattice_) return kMiss;
    if (n * dim > kLatticeCoordinates) {
      const Moments moments = moments_of(disc, particles, c);
      if (moments.non_tensor > kTensorTolerance) return kMiss;
      const std::uint64_t code = moment_code(disc, c, moments, false);
      const auto it = code == 0 ? moment_boxes_.end() : moment_boxes_.find(code);
      return it == moment_boxes_.end() ? kMiss
                                       : (1.0 - kTensorSlope * moments.non_tensor) * it->second;
    }
    if (static_cast<int>(last_code_.size()) != disc.num_cells()) return kMiss;
    const SmallLayout layout = small_layout(disc, particles, c);
    const int masses = seen_masses(layout), poisson = seen_poisson(disc, c);
    if (masses < 0 || poisson < 0) return kMiss;
    const std::uint64_t code = lattice_code(layout, masses, poisson, nullptr);
    if (code == 0) return kMiss;
    // Particles cross a box every few steps at most: the cell's last box first.
    if (last_code_[c] == code) return last_courant_[c];
    if (const auto it = boxes_.find(code); it != boxes_.end()) {
      last_code_[c] = code;
      return last_courant_[c] = it->second;
    }
    return kMiss;
  }
  static constexpr double kMiss = std::numeric_limits<double>::quiet_NaN();

  // A lattice layout's particles (at most kLatticeCoordinates coordinates), as they are, sorted:
  // entries_ without the shared buffer, for the threads.
  struct SmallLayout {
    std::array<Entry, kLatticeCoordinates> entry{};
    int n = 0;
  };
  static SmallLayout small_layout(const Disc& disc, const ParticleSet& particles, int c) {
    SmallLayout layout;
    layout.n = std::min(disc.cell_end(c) - disc.cell_begin(c), kLatticeCoordinates / dim);
    for (int k = 0; k < layout.n; ++k) {
      const int p = disc.entry_particle(disc.cell_begin(c) + k);
      for (int a = 0; a < dim; ++a) layout.entry[k].x[a] = disc.particle_local(p)[a];
      layout.entry[k].mass = particles.mass[p];
    }
    for (int k = 1; k < layout.n; ++k)  // insertion sort: at most four entries
      for (int j = k; j > 0 && layout.entry[j] < layout.entry[j - 1]; --j)
        std::swap(layout.entry[j], layout.entry[j - 1]);
    return layout;
  }

  // The box code of a lattice layout: its count (3 bits), the boxes (8 bits per coordinate, also
  // written to `box` when given), its masses' index (16) and Poisson's (8); 0 when an index has no
  // room.
  static std::uint64_t lattice_code(const SmallLayout& layout, int masses, int poisson,
                                    std::array<int, kLatticeCoordinates>* box) {
    if (masses >= (1 << 16) || poisson >= (1 << 8)) return 0;
    std::uint64_t code = static_cast<std::uint64_t>(layout.n);
    for (int k = 0; k < layout.n; ++k)
      for (int a = 0; a < dim; ++a) {
        const int b = Lattice::box(layout.entry[k].x[a]);
        if (box) (*box)[k * dim + a] = b;
        code = code << 8 | static_cast<std::uint64_t>(b);
      }
    code = code << 16 | static_cast<std::uint64_t>(masses);
    return code << 8 | static_cast<std::uint64_t>(poisson);
  }

  // masses_index and poisson_index without adding: -1 when not seen yet.
  int seen_masses(const SmallLayout& layout) const {
    const double unit = layout.entry[0].mass;
    bool equal = true;
    for (int k = 0; k < layout.n; ++k) equal = equal && layout.entry[k].mass == unit;
    if (equal) return 0;
    for (std::size_t i = 0; i < masses_seen_.size(); ++i) {
      const auto& seen = masses_seen_[i];
      bool same = static_cast<int>(seen.size()) == layout.n;
      for (int k = 0; same && k < layout.n; ++k) same = seen[k] == layout.entry[k].mass / unit;
      if (same) return 1 + static_cast<int>(i);
    }
    return -1;
  }
  int seen_poisson(const Disc& disc, int c) const {
    if constexpr (dim == 1) {
      return 0;
    } else {
      const auto it =
          std::find(poisson_seen_.begin(), poisson_seen_.end(), disc.cell_material(c).poisson);
      return it == poisson_seen_.end() ? -1 : static_cast<int>(it - poisson_seen_.begin());
    }
  }

  // Cell c's particles as entries (positions rounded to `quantum`, 0: as they are), sorted.
  void fill_entries(const Disc& disc, const ParticleSet& particles, int c, double quantum) {
    entries_.clear();
    for (int e = disc.cell_begin(c); e < disc.cell_end(c); ++e) {
      const int p = disc.entry_particle(e);
      Entry entry;
      for (int a = 0; a < dim; ++a) {
        const double xi = disc.particle_local(p)[a];
        entry.x[a] = quantum > 0 ? quantise_position(xi, quantum) : xi;
      }
      entry.mass = particles.mass[p];
      entries_.push_back(entry);
    }
    // A lone particle's one-step map does not depend on where it sits (lib's update reduces to
    // the upwind finite-volume one; tests/stability_von_neumann.cpp checks C* = 1 from xi = 0 to
    // 1 and next to the nodes), but for RK2 in 2D: where shared, all such cells take the key of
    // the centre.
    if (entries_.size() == 1 && lone_particle_shared_) entries_.front().x.fill(0.5);
    std::sort(entries_.begin(), entries_.end());
  }

  // key_ from entries_ (and the cell's Poisson ratio): the smallest key over the entries' images
  // under the mirrors x -> 1 - x (each axis) and, in square 2D cells, the swap of x and y.
  void fill_key(const Disc& disc, int c) {
    const int images = (1 << dim) * (swap_symmetric_ ? 2 : 1);
    best_key_.clear();
    for (int m = 0; m < images; ++m) {
      image_ = entries_;
      for (auto& entry : image_) {
        for (int a = 0; a < dim; ++a)
          if ((m >> a) & 1) entry.x[a] = 1.0 - entry.x[a];
        if (m >> dim) std::swap(entry.x[0], entry.x[dim - 1]);
      }
      std::sort(image_.begin(), image_.end());
      const double unit = image_.front().mass;  // the analysis rescales masses to a full cell
      key_.clear();
      if constexpr (dim > 1) key_.push_back(disc.cell_material(c).poisson);
      for (const auto& entry : image_)
        for (int a = 0; a < dim; ++a) key_.push_back(entry.x[a]);
      for (const auto& entry : image_) key_.push_back(entry.mass / unit);
      if (m == 0 || key_ < best_key_) best_key_.swap(key_);
    }
    key_.swap(best_key_);
  }

  stability::CellLayout key_layout() const {
    const auto n = static_cast<std::ptrdiff_t>((key_.size() - key_prefix) / (dim + 1));
    const auto first = key_.begin() + key_prefix;
    return {std::vector<double>(first, first + dim * n),
            std::vector<double>(first + dim * n, key_.end()), dim};
  }

  // C* of entries_ (in cell c's material), through the cache.
  double analysed(const Disc& disc, int c) {
    fill_key(disc, c);
    const auto it = cache_.find(key_);
    if (it != cache_.end()) return it->second;
    const auto start = std::chrono::steady_clock::now();
    const double courant = analyse(key_layout(), setting_of(disc, c));
    cache_.emplace(key_, courant);
    analysis_seconds_ +=
        std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
    return courant;
  }

  stability::AnalysisSetting setting_of(const Disc& disc, int c) const {
    stability::AnalysisSetting setting = setting_;
    if constexpr (dim > 1) setting.poisson = disc.cell_material(c).poisson;
    return setting;
  }
  // C* of a layout under the scene's criterion. A lattice `corner`'s C* is only a bound for the
  // layouts of its boxes: three significant digits, rounded down, do (a third of the cost of the
  // full resolution for off-centre RK2 particles, whose L2 limit just below 1 takes many
  // refinements; the monotone criterion is cheap and keeps its resolution).
  double analyse(const stability::CellLayout& layout, const stability::AnalysisSetting& setting,
                 bool corner = false) const {
    if (criterion_ == stability::Criterion::monotone)
      return stability::admissible_courant(layout, setting, criterion_).courant;
    stability::SearchOptions options = stability::default_search_options(stability::Criterion::l2);
    if (corner) {
      options.courant_tolerance = 1e-4;
      options.significant_digits = 3;
    }
    const stability::OneStepMap map = stability::build_one_step_map(layout, setting);
    const stability::CourantResult strict =
        stability::admissible_courant(map, stability::Criterion::l2, options);
    return criterion_ == stability::Criterion::budget
               ? stability::budgeted_courant(map, strict, budget_).courant
               : strict.courant;
  }

  // Lattice corners not analysed yet (`missing`, their keys), analysed on threads (each analysis
  // gives the same answer whatever the thread count) into corner_cache_.
  void analyse_corners(const Disc& disc, int c, const std::vector<std::vector<double>>& missing,
                       const std::vector<stability::CellLayout>& layouts) {
    if (missing.empty()) return;
    const auto start = std::chrono::steady_clock::now();
    const stability::AnalysisSetting setting = setting_of(disc, c);
    std::vector<double> found(missing.size());
    std::exception_ptr failure;  // an exception must not leave a parallel region
#pragma omp parallel for schedule(dynamic) if (missing.size() > 1)
    for (std::size_t i = 0; i < missing.size(); ++i) {
      try {
        found[i] = analyse(layouts[i], setting, true);
      } catch (...) {
#pragma omp critical(dgmpm_corner_failure)
        if (!failure) failure = std::current_exception();
      }
    }
    if (failure) std::rethrow_exception(failure);
    for (std::size_t i = 0; i < missing.size(); ++i) corner_cache_.emplace(missing[i], found[i]);
    analysis_seconds_ +=
        std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  }

  // The smallest C* over the corners of the lattice box holding cell c's layout (moving
  // particles, at most kLatticeCoordinates coordinates), through the box cache.
  double lattice_courant(const Disc& disc, const ParticleSet& particles, int c) {
    const SmallLayout layout = small_layout(disc, particles, c);
    entries_.assign(layout.entry.begin(), layout.entry.begin() + layout.n);
    std::array<int, kLatticeCoordinates> box{};
    const std::uint64_t code = lattice_code(layout, masses_index(), poisson_index(disc, c), &box);
    if (code == 0) {  // beyond the code: rounded as large ones
      fill_entries(disc, particles, c, quantum_);
      return analysed(disc, c);
    }
    if (const auto it = boxes_.find(code); it != boxes_.end()) return it->second;
    // The smallest C* over the box's corners, the particles moved onto them.
    const int n = layout.n;
    const auto& points = Lattice::points();
    const double courant = smallest_over_corners(disc, c, 1 << (n * dim), [&](int corner) {
      entries_.assign(layout.entry.begin(), layout.entry.begin() + n);
      for (int k = 0; k < n; ++k)
        for (int a = 0; a < dim; ++a)
          entries_[k].x[a] = points[box[k * dim + a] + ((corner >> (k * dim + a)) & 1)];
    });
    boxes_.emplace(code, courant);
    return courant;
  }

  // The smallest C* over a box's corners, `place(corner)` filling entries_ with each corner's
  // layout: corners not analysed yet are analysed (on threads) into corner_cache_.
  template <class Place>
  double smallest_over_corners(const Disc& disc, int c, int corners, Place&& place) {
    std::vector<std::vector<double>> keys, missing;
    std::vector<stability::CellLayout> layouts;
    for (int corner = 0; corner < corners; ++corner) {
      place(corner);
      std::sort(entries_.begin(), entries_.end());
      fill_key(disc, c);
      keys.push_back(key_);
      if (!corner_cache_.count(key_) &&
          std::find(missing.begin(), missing.end(), key_) == missing.end()) {
        missing.push_back(key_);
        layouts.push_back(key_layout());
      }
    }
    analyse_corners(disc, c, missing, layouts);
    double courant = std::numeric_limits<double>::infinity();
    for (const auto& key : keys) courant = std::min(courant, corner_cache_.at(key));
    return courant;
  }

  // A cell's layout seen through its mass moments (local coordinates, weighted by mass, over the
  // cell's mass), which are all its C* depends on (docs/method.md): per axis the mean mu and the
  // spread, the standard deviation as a fraction of the largest a layout of that mean can have,
  // sqrt(mu (1 - mu)) (so that near a node it scales with the distance to it, as the mean's
  // lattice does); and how far it is from the tensor product of those marginals: the largest
  // |M_ab - M_a0 M_0b| over a, b in {1, 2}, M_ab = sum m x^a y^b / sum m (0 in 1D).
  struct Moments {
    std::array<double, dim> mean{}, spread{};
    double non_tensor = 0;
  };
  static Moments moments_of(const Disc& disc, const ParticleSet& particles, int c) {
    std::array<std::array<double, 3>, 3> sum{};  // sum m x^a y^b, a, b <= 2 (b = 0 in 1D)
    for (int e = disc.cell_begin(c); e < disc.cell_end(c); ++e) {
      const int p = disc.entry_particle(e);
      const auto xi = disc.particle_local(p);
      const double x = xi[0], y = dim > 1 ? xi[dim - 1] : 0.0, m = particles.mass[p];
      const std::array<double, 3> px{1.0, x, x * x}, py{1.0, y, y * y};
      for (int a = 0; a < 3; ++a)
        for (int b = 0; b < (dim > 1 ? 3 : 1); ++b) sum[a][b] += m * px[a] * py[b];
    }
    Moments moments;
    const double mass = sum[0][0];
    for (int axis = 0; axis < dim; ++axis) {
      const double first = axis == 0 ? sum[1][0] / mass : sum[0][1] / mass;
      const double second = axis == 0 ? sum[2][0] / mass : sum[0][2] / mass;
      const double largest = first * (1.0 - first);
      moments.mean[axis] = first;
      moments.spread[axis] =
          largest > 0 ? std::sqrt(std::clamp((second - first * first) / largest, 0.0, 1.0)) : 0.0;
    }
    if constexpr (dim > 1)
      for (int a = 1; a <= 2; ++a)
        for (int b = 1; b <= 2; ++b)
          moments.non_tensor =
              std::max(moments.non_tensor,
                       std::abs(sum[a][b] / mass - sum[a][0] / mass * (sum[0][b] / mass)));
    return moments;
  }

  // The moment lattice: per axis the position lattice for the mean, and for the spread (0 to 1)
  // the points (k - 1/2) / kSpreads, so that the spreads of regular n x n seedings (1/2 for
  // n = 2, 0.544 for 3) lie inside a box, not on a face where drift would visit two boxes. A
  // box's code: per axis the two box indices (8 bits each), then the Poisson ratio's index.
  static constexpr int kSpreads = dim == 1 ? 32 : 16;
  static double spread_point(int k) {
    return k == 0 ? 0.0 : std::min(1.0, (k - 0.5) / kSpreads);
  }
  static int spread_box(double spread) {  // [spread_point(k), spread_point(k + 1)]
    return std::clamp(static_cast<int>(spread * kSpreads + 0.5), 0, kSpreads);
  }

  // Layouts this close to a tensor product (non_tensor <= kTensorTolerance) take their
  // marginals' box, lowered by kTensorSlope times non_tensor relative; farther ones are analysed
  // as they are. Sheared 2 x 2 and 3 x 3 layouts (DCU and CTU Euler, DCU RK2, centred and off
  // centre) change C* by at most 2.7 non_tensor relative (tests/solver_time_step_2d.cpp checks
  // the slope with room to spare).
  static constexpr double kTensorTolerance = 2e-3, kTensorSlope = 5.0;

  // One axis's layout of the given mean and (relative) spread as at most two weighted points in
  // [0, 1]: equal weights at mean -+ the standard deviation where both lie in the cell, else one
  // point on the nearer node.
  static int marginal_points(double mean, double spread, std::array<double, 2>& x,
                             std::array<double, 2>& w) {
    const double variance = spread * spread * mean * (1.0 - mean);
    const double deviation = std::sqrt(variance);
    if (variance <= 0) {
      x = {mean, mean};
      w = {1.0, 0.0};
      return 1;
    }
    if (deviation <= std::min(mean, 1.0 - mean)) {
      x = {mean - deviation, mean + deviation};
      w = {0.5, 0.5};
    } else if (mean < 0.5) {  // a point on node 0 and one at mean + variance / mean
      const double b = std::min(1.0, mean + variance / mean);
      x = {0.0, b};
      w = {1.0 - mean / b, mean / b};
    } else {  // the mirror image
      const double a = std::max(0.0, mean - variance / (1.0 - mean));
      x = {a, 1.0};
      w = {(1.0 - mean) / (1.0 - a), 1.0 - (1.0 - mean) / (1.0 - a)};
    }
    return 2;
  }

  // The box code of cell c's moments; 0 when its Poisson ratio has no index yet and `add` is
  // false (the threads' read-only lookup) or has no room in the code.
  std::uint64_t moment_code(const Disc& disc, int c, const Moments& moments, bool add) {
    std::uint64_t code = 1;
    for (int a = 0; a < dim; ++a)
      code = code << 16 | static_cast<std::uint64_t>(Lattice::box(moments.mean[a])) << 8 |
             static_cast<std::uint64_t>(spread_box(moments.spread[a]));
    int poisson = 0;
    if constexpr (dim > 1) {
      const double nu = disc.cell_material(c).poisson;
      const auto it = std::find(poisson_seen_.begin(), poisson_seen_.end(), nu);
      if (it != poisson_seen_.end())
        poisson = static_cast<int>(it - poisson_seen_.begin());
      else if (add)
        poisson = poisson_index(disc, c);
      else
        return 0;
    }
    if (poisson >= (1 << 8)) return 0;
    return code << 8 | static_cast<std::uint64_t>(poisson);
  }

  // The smallest C* over the corners of the moment box of cell c's layout, lowered for its
  // distance from a tensor product; NaN for a layout too far from one (analysed as it is).
  double moment_courant(const Disc& disc, const ParticleSet& particles, int c) {
    const Moments moments = moments_of(disc, particles, c);
    if (moments.non_tensor > kTensorTolerance) return kMiss;
    const std::uint64_t code = moment_code(disc, c, moments, true);
    if (code == 0) return kMiss;
    const double shear = 1.0 - kTensorSlope * moments.non_tensor;
    if (const auto it = moment_boxes_.find(code); it != moment_boxes_.end())
      return shear * it->second;
    std::array<int, dim> mean_box{}, spread_box_of{};
    for (int a = 0; a < dim; ++a) {
      mean_box[a] = Lattice::box(moments.mean[a]);
      spread_box_of[a] = spread_box(moments.spread[a]);
    }
    const auto& points = Lattice::points();
    const double courant = smallest_over_corners(disc, c, 1 << (2 * dim), [&](int corner) {
      // Per axis a mean and a spread of the box's corners, and their points.
      std::array<std::array<double, 2>, dim> x{}, w{};
      std::array<int, dim> count{};
      for (int a = 0; a < dim; ++a) {
        const double mean = points[mean_box[a] + ((corner >> (2 * a)) & 1)];
        const double spread = spread_point(spread_box_of[a] + ((corner >> (2 * a + 1)) & 1));
        count[a] = marginal_points(mean, spread, x[a], w[a]);
      }
      entries_.clear();  // the tensor product of the axes' points
      for (int i = 0; i < count[0]; ++i)
        for (int j = 0; j < (dim > 1 ? count[dim - 1] : 1); ++j) {
          Entry entry;
          entry.x[0] = x[0][i];
          entry.mass = w[0][i];
          if constexpr (dim > 1) {
            entry.x[1] = x[1][j];
            entry.mass *= w[1][j];
          }
          entries_.push_back(entry);
        }
    });
    moment_boxes_.emplace(code, courant);
    return shear * courant;
  }

  // 0 for equal masses, else 1 + the index of entries_' relative masses among those seen.
  int masses_index() {
    bool equal = true;
    for (const auto& e : entries_) equal = equal && e.mass == entries_.front().mass;
    if (equal) return 0;
    relative_.clear();
    for (const auto& e : entries_) relative_.push_back(e.mass / entries_.front().mass);
    const auto it = std::find(masses_seen_.begin(), masses_seen_.end(), relative_);
    if (it != masses_seen_.end()) return 1 + static_cast<int>(it - masses_seen_.begin());
    masses_seen_.push_back(relative_);
    return static_cast<int>(masses_seen_.size());
  }
  int poisson_index(const Disc& disc, int c) {
    if constexpr (dim == 1) {
      return 0;
    } else {
      const double nu = disc.cell_material(c).poisson;
      const auto it = std::find(poisson_seen_.begin(), poisson_seen_.end(), nu);
      if (it != poisson_seen_.end()) return static_cast<int>(it - poisson_seen_.begin());
      poisson_seen_.push_back(nu);
      return static_cast<int>(poisson_seen_.size()) - 1;
    }
  }
};

}  // namespace dgmpm
