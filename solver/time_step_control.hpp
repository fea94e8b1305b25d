#pragma once
// Time step control: dt = C h / c from a fixed Courant number, or, with "courant": "auto",
// dt = S min over occupied cells of min(1, f) C*(layout) h / c_cell, C* being the admissible
// Courant number of the cell's particle layout from stability/ (the analysis of the operators the
// solver runs) and f the cell's fill: its particles' mass over rho times its volume. h is the
// smallest cell size, c the largest wave speed of the cell's material.
//
// The fill factor is the small-cell rule: a partly filled cell (a body ending inside it) has
// nodal masses f times those of the full layout the analysis assumes, while the face fluxes are
// unchanged, so waves cross it as if it were f h long. The periodic model cannot see this (every
// cell is full there); tests/solver_time_step.cpp checks the rule against the spectral radius of
// the whole scene's operator.

#include "solver/scene.hpp"

#include <dgmpm/discretisation.hpp>
#include <dgmpm/grid.hpp>
#include <stability/admissible_courant.hpp>
#include <stability/layout.hpp>
#include <stability/options.hpp>

#include <algorithm>
#include <array>
#include <cmath>
#include <limits>
#include <map>
#include <set>
#include <vector>

namespace dgmpm {

// Positions (local coordinates) are rounded before the analysis, so that the cache serves
// layouts equal but for round-off (fixed particles) or drifting slowly (moving particles): to
// multiples of a quantum, except near a node, where C* varies like the distance d to it: there
// d keeps 8 significant bits (relative error 2^-9, finer than the quantum below 2^8 quanta).
// Below half a quantum the particle is put on the node: the resolution of the cache. Some
// layouts have C* -> 0 as d -> 0 but C* = 1 at d = 0 ({0, 1 - d}); resolving them would let a
// layout that moving particles pass through in a step or two stall the run (dt ~ d h / c).
// tests/solver_time_step_quantisation.cpp measures the error on both sides of q / 2.
struct LayoutQuantisation {
  static constexpr double fixed_position_quantum = 1e-9;
  static constexpr double moving_position_quantum = 1.0 / 4096;
  static constexpr int node_distance_bits = 8;
  // The rounded local position: onto the node if d = min(xi, 1 - xi) < quantum / 2, else moved
  // by at most min(quantum / 2, d 2^-9).
  static double quantise_position(double xi, double quantum);
};

template <class Physics>
class TimeStepControl : public LayoutQuantisation {
 public:
  static constexpr int dim = Physics::dim;
  using Disc = Discretisation<Physics>;
  using ParticleSet = Particles<dim, Physics::n_comp>;

  // Throws scene::SceneError for a criterion the analysis cannot apply (2D elastic monotone).
  explicit TimeStepControl(const scene::Scene& scene)
      : automatic_(scene.time.courant_auto), courant_(scene.time.courant),
        safety_(scene.time.safety),
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
          "not split into the scalar waves the criterion needs; allowed: \"l2\"");
    // A lone particle's map does not depend on where it sits, but for RK2 in 2D (the second
    // stage sees the unequal nodal masses of an off-centre particle).
    lone_particle_shared_ = dim == 1 || setting_.time == TimeScheme::euler;
  }

  bool automatic() const { return automatic_; }

  // Time step of the current configuration. Fixed Courant: C h / max c over occupied cells.
  double time_step(const Grid<dim>& grid, const Disc& disc, const ParticleSet& particles) {
    const double h = grid.cell_size.minCoeff();
    double dt = std::numeric_limits<double>::infinity();
    for (int c = 0; c < disc.num_cells(); ++c) {
      if (!disc.occupied(c)) continue;
      const double speed = Physics::max_wave_speed(disc.cell_material(c));
      const double cs = automatic_ ? safety_ * cell_courant(disc, particles, c) : courant_;
      dt = std::min(dt, cs * h / speed);
    }
    return dt;
  }

  // The smallest admissible Courant number over the occupied cells, the cell that sets it and
  // its layout (as analysed).
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
  // would analyse), without analysing them.
  int layouts_to_analyse(const Disc& disc, const ParticleSet& particles) {
    std::set<std::vector<double>> keys;
    for (int c = 0; c < disc.num_cells(); ++c) {
      if (!disc.occupied(c)) continue;
      if (disc.cell_end(c) - disc.cell_begin(c) == 1 && lone_particle_shared_ &&
          lone_particle_courant_ > 0.0)
        continue;
      fill_key(disc, particles, c);
      if (!cache_.count(key_)) keys.insert(key_);
    }
    return static_cast<int>(keys.size());
  }

  // Distinct layouts analysed so far (cache misses).
  int layouts_analysed() const { return static_cast<int>(cache_.size()); }

  // The layout of cell c as analysed: positions (quantised when particles move) sorted, masses
  // relative to the first one.
  stability::CellLayout layout_of(const Disc& disc, const ParticleSet& particles, int c) {
    fill_key(disc, particles, c);
    return key_layout();
  }

  // Admissible Courant number of cell c's layout, through the cache (no allocation on a hit),
  // times min(1, fill).
  double cell_courant(const Disc& disc, const ParticleSet& particles, int c) {
    const double small_cell = std::min(1.0, disc.fill(c));
    const bool lone = disc.cell_end(c) - disc.cell_begin(c) == 1 && lone_particle_shared_;
    if (lone && lone_particle_courant_ > 0.0)
      return small_cell * lone_particle_courant_;  // the common case, without building a key
    fill_key(disc, particles, c);
    const auto it = cache_.find(key_);
    if (it != cache_.end()) return small_cell * it->second;
    stability::AnalysisSetting setting = setting_;
    if constexpr (dim > 1) setting.poisson = disc.cell_material(c).poisson;
    const double courant = stability::admissible_courant(key_layout(), setting, criterion_).courant;
    cache_.emplace(key_, courant);
    if (lone && dim == 1) lone_particle_courant_ = courant;  // 2D: one entry per Poisson ratio
    return small_cell * courant;
  }

 private:
  bool automatic_;
  double courant_, safety_, quantum_;
  stability::Criterion criterion_;
  stability::AnalysisSetting setting_;
  bool lone_particle_shared_ = true;
  // Key: (2D: Poisson's ratio), positions (dim per particle, sorted), then relative masses.
  std::map<std::vector<double>, double> cache_;
  double lone_particle_courant_ = -1;  // the one-particle entry, once analysed
  struct Entry {
    std::array<double, dim> x;
    double mass;
    bool operator<(const Entry& o) const { return x < o.x || (x == o.x && mass < o.mass); }
  };
  std::vector<Entry> entries_;
  std::vector<double> key_;
  static constexpr int key_prefix = dim > 1 ? 1 : 0;  // Poisson's ratio in 2D

  void fill_key(const Disc& disc, const ParticleSet& particles, int c) {
    entries_.clear();
    for (int e = disc.cell_begin(c); e < disc.cell_end(c); ++e) {
      const int p = disc.entry_particle(e);
      Entry entry;
      for (int a = 0; a < dim; ++a)
        entry.x[a] = quantise_position(disc.particle_local(p)[a], quantum_);
      entry.mass = particles.mass[p];
      entries_.push_back(entry);
    }
    // A lone particle's one-step map does not depend on where it sits (lib's update reduces to
    // the upwind finite-volume one; tests/stability_von_neumann.cpp checks C* = 1 from xi = 0 to
    // 1 and next to the nodes), but for RK2 in 2D: where shared, all such cells take the key of
    // the centre.
    if (entries_.size() == 1 && lone_particle_shared_) entries_.front().x.fill(0.5);
    std::sort(entries_.begin(), entries_.end());
    const double unit = entries_.front().mass;  // the analysis rescales masses to a full cell
    key_.clear();
    if constexpr (dim > 1) key_.push_back(disc.cell_material(c).poisson);
    for (const auto& entry : entries_)
      for (int a = 0; a < dim; ++a) key_.push_back(entry.x[a]);
    for (const auto& entry : entries_) key_.push_back(entry.mass / unit);
  }

  stability::CellLayout key_layout() const {
    const auto n = static_cast<std::ptrdiff_t>((key_.size() - key_prefix) / (dim + 1));
    const auto first = key_.begin() + key_prefix;
    return {std::vector<double>(first, first + dim * n),
            std::vector<double>(first + dim * n, key_.end()), dim};
  }
};

}  // namespace dgmpm
