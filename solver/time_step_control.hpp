#pragma once
// Time step control: dt = C h / c from a fixed Courant number, or, with "courant": "auto",
// dt = S min over occupied cells of min(1, f) C*(layout) h / c_cell, C* being the admissible
// Courant number of the cell's particle layout from stability/ (the analysis of the operators the
// solver runs) and f the cell's fill: its particles' mass over rho times its volume.
//
// The fill factor is the small-cell rule: a partly filled cell (a body ending inside it) has
// nodal masses f times those of the full layout the analysis assumes, while the face fluxes are
// unchanged, so waves cross it as if it were f h long. The periodic model cannot see this (every
// cell is full there); tests/solver_time_step.cpp checks the rule against the spectral radius of
// the whole scene's operator.

#include "solver/scene.hpp"

#include <dgmpm/discretisation.hpp>
#include <dgmpm/physics/elastic_bar.hpp>
#include <stability/layout.hpp>
#include <stability/options.hpp>

#include <map>
#include <vector>

namespace dgmpm {

class TimeStepControl {
 public:
  using Disc = Discretisation<ElasticBar>;
  using BarParticles = Particles<1, ElasticBar::n_comp>;

  // Positions (local coordinates) are rounded before the analysis, so that the cache serves
  // layouts equal but for round-off (fixed particles) or drifting slowly (moving particles): to
  // multiples of a quantum, except near a node, where C* varies like the distance d to it: there
  // d keeps 8 significant bits (relative error 2^-9, finer than the quantum below 2^8 quanta).
  // Below half a quantum the particle is put on the node: the resolution of the cache. Some
  // layouts have C* -> 0 as d -> 0 but C* = 1 at d = 0 ({0, 1 - d}); resolving them would let a
  // layout that moving particles pass through in a step or two stall the run (dt ~ d h / c).
  // tests/solver_time_step_quantisation.cpp measures the error on both sides of q / 2.
  static constexpr double fixed_position_quantum = 1e-9;
  static constexpr double moving_position_quantum = 1.0 / 4096;
  static constexpr int node_distance_bits = 8;
  // The rounded local position: onto the node if d = min(xi, 1 - xi) < quantum / 2, else moved
  // by at most min(quantum / 2, d 2^-9).
  static double quantise_position(double xi, double quantum);

  TimeStepControl(const scene::TimeSpec& time, bool particles_move);

  bool automatic() const { return automatic_; }

  // Time step of the current configuration. Fixed Courant: C h / max c over occupied cells.
  double time_step(const Disc& disc, const BarParticles& particles, double h);

  // The smallest admissible Courant number over the occupied cells, the cell that sets it and
  // its layout (as analysed).
  struct Limit {
    double courant = 0;  // min(1, fill) C*(layout)
    int cell = -1;
    double fill = 1;
    stability::CellLayout layout;
  };
  Limit smallest_admissible(const Disc& disc, const BarParticles& particles, double cell_volume);

  // Distinct layouts analysed so far (cache misses).
  int layouts_analysed() const { return static_cast<int>(cache_.size()); }

  // The layout of cell c as analysed: positions (quantised when particles move) sorted, masses
  // relative to the first one.
  stability::CellLayout layout_of(const Disc& disc, const BarParticles& particles, int c);

  // Admissible Courant number of cell c's layout, through the cache (no allocation on a hit),
  // times min(1, fill).
  double cell_courant(const Disc& disc, const BarParticles& particles, int c, double cell_volume);

  // Mass of cell c's particles over rho times the cell's volume.
  static double fill(const Disc& disc, int c, double cell_volume) {
    return disc.cell_mass(c) / (disc.cell_material(c).density * cell_volume);
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

  void fill_key(const Disc& disc, const BarParticles& particles, int c);
  stability::CellLayout key_layout() const;  // the layout key_ describes
};

}  // namespace dgmpm
