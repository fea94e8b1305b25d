#pragma once
// Time step control: dt = C h / c from a fixed Courant number, or, with "courant": "auto",
// dt = S min over occupied cells of C*(layout) h / c_cell, C* being the admissible Courant number
// of the cell's particle layout from stability/ (the analysis of the operators the solver runs).

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

  // Positions (local coordinates) are rounded to multiples of a quantum before the analysis, so
  // that the cache serves layouts equal but for round-off (fixed particles) or drifting slowly
  // (moving particles).
  static constexpr double fixed_position_quantum = 1e-9;
  static constexpr double moving_position_quantum = 1.0 / 4096;

  TimeStepControl(const scene::TimeSpec& time, bool particles_move);

  bool automatic() const { return automatic_; }

  // Time step of the current configuration. Fixed Courant: C h / max c over occupied cells.
  double time_step(const Disc& disc, const BarParticles& particles, double h);

  // The smallest admissible Courant number over the occupied cells, the cell that sets it and
  // its layout (as analysed).
  struct Limit {
    double courant = 0;
    int cell = -1;
    stability::CellLayout layout;
  };
  Limit smallest_admissible(const Disc& disc, const BarParticles& particles);

  // Distinct layouts analysed so far (cache misses).
  int layouts_analysed() const { return static_cast<int>(cache_.size()); }

  // The layout of cell c as analysed: positions (quantised when particles move) sorted, masses
  // relative to the first one.
  stability::CellLayout layout_of(const Disc& disc, const BarParticles& particles, int c);

  // Admissible Courant number of cell c's layout, through the cache: no allocation on a hit.
  double cell_courant(const Disc& disc, const BarParticles& particles, int c);

 private:
  bool automatic_;
  double courant_, safety_, quantum_;
  stability::TimeScheme scheme_;
  stability::Criterion criterion_;
  std::map<std::vector<double>, double> cache_;  // key: positions then relative masses
  std::vector<std::pair<double, double>> entries_;
  std::vector<double> key_;

  void fill_key(const Disc& disc, const BarParticles& particles, int c);
  stability::CellLayout key_layout() const;  // the layout key_ describes
};

}  // namespace dgmpm
