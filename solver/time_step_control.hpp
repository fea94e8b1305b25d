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
#include <cmath>
#include <limits>
#include <map>
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

  // Throws scene::SceneError for "auto" where no layout analysis exists yet (2D).
  TimeStepControl(const scene::Scene& scene)
      : automatic_(scene.time.courant_auto), courant_(scene.time.courant),
        safety_(scene.time.safety),
        quantum_(scene.particles_move ? moving_position_quantum : fixed_position_quantum),
        scheme_(scene.time.integrator), criterion_(scene.time.criterion) {
    if (automatic_ && dim > 1)
      throw scene::SceneError(scene.source +
                              ": time.courant: value \"auto\" is not available in 2D yet; "
                              "allowed: a number > 0");
  }

  bool automatic() const { return automatic_; }

  // Time step of the current configuration. Fixed Courant: C h / max c over occupied cells.
  double time_step(const Grid<dim>& grid, const Disc& disc, const ParticleSet& particles) {
    const double h = grid.cell_size.minCoeff(), volume = grid.cell_volume();
    double dt = std::numeric_limits<double>::infinity();
    for (int c = 0; c < disc.num_cells(); ++c) {
      if (!disc.occupied(c)) continue;
      const double speed = Physics::max_wave_speed(disc.cell_material(c));
      double cs = courant_;
      if constexpr (dim == 1)
        if (automatic_) cs = safety_ * cell_courant(disc, particles, c, volume);
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
  Limit smallest_admissible(const Disc& disc, const ParticleSet& particles,
                            double cell_volume) requires(dim == 1) {
    Limit limit;
    limit.courant = std::numeric_limits<double>::infinity();
    for (int c = 0; c < disc.num_cells(); ++c) {
      if (!disc.occupied(c)) continue;
      const double cs = cell_courant(disc, particles, c, cell_volume);
      if (cs < limit.courant)
        limit = {cs, c, fill(disc, c, cell_volume), layout_of(disc, particles, c)};
    }
    return limit;
  }

  // Distinct layouts analysed so far (cache misses).
  int layouts_analysed() const { return static_cast<int>(cache_.size()); }

  // The layout of cell c as analysed: positions (quantised when particles move) sorted, masses
  // relative to the first one.
  stability::CellLayout layout_of(const Disc& disc, const ParticleSet& particles,
                                  int c) requires(dim == 1) {
    fill_key(disc, particles, c);
    return key_layout();
  }

  // Admissible Courant number of cell c's layout, through the cache (no allocation on a hit),
  // times min(1, fill).
  double cell_courant(const Disc& disc, const ParticleSet& particles, int c,
                      double cell_volume) requires(dim == 1) {
    const double small_cell = std::min(1.0, fill(disc, c, cell_volume));
    if (disc.cell_end(c) - disc.cell_begin(c) == 1 && lone_particle_courant_ > 0.0)
      return small_cell * lone_particle_courant_;  // the common case, without building a key
    fill_key(disc, particles, c);
    const auto it = cache_.find(key_);
    if (it != cache_.end()) return small_cell * it->second;
    const double courant =
        stability::admissible_courant(key_layout(), scheme_, criterion_, stability::Model::elastic)
            .courant;
    cache_.emplace(key_, courant);
    if (key_.size() == 2) lone_particle_courant_ = courant;
    return small_cell * courant;
  }

  // Mass of cell c's particles over rho times the cell's volume.
  static double fill(const Disc& disc, int c, double cell_volume) {
    return disc.cell_mass(c) / (Physics::density(disc.cell_material(c)) * cell_volume);
  }

 private:
  bool automatic_;
  double courant_, safety_, quantum_;
  stability::TimeScheme scheme_;
  stability::Criterion criterion_;
  std::map<std::vector<double>, double> cache_;  // key: positions then relative masses
  double lone_particle_courant_ = -1;            // the one-particle entry, once analysed
  std::vector<std::pair<double, double>> entries_;
  std::vector<double> key_;

  void fill_key(const Disc& disc, const ParticleSet& particles, int c) {
    entries_.clear();
    for (int e = disc.cell_begin(c); e < disc.cell_end(c); ++e) {
      const int p = disc.entry_particle(e);
      entries_.emplace_back(quantise_position(disc.particle_local(p)[0], quantum_),
                            particles.mass[p]);
    }
    // A lone particle's one-step map does not depend on where it sits (lib's update reduces to
    // the upwind finite-volume one; tests/stability_von_neumann.cpp checks C* = 1 from xi = 0 to
    // 1 and next to the nodes): all such cells share the key of the first one analysed.
    if (entries_.size() == 1) entries_.front().first = 0.5;
    std::sort(entries_.begin(), entries_.end());
    const double unit = entries_.front().second;  // the analysis rescales masses to a full cell
    key_.clear();
    for (const auto& entry : entries_) key_.push_back(entry.first);
    for (const auto& entry : entries_) key_.push_back(entry.second / unit);
  }

  stability::CellLayout key_layout() const {
    const auto n = static_cast<std::ptrdiff_t>(key_.size() / 2);
    return {std::vector<double>(key_.begin(), key_.begin() + n),
            std::vector<double>(key_.begin() + n, key_.end())};
  }
};

}  // namespace dgmpm
