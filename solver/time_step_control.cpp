#include "solver/time_step_control.hpp"

#include <stability/admissible_courant.hpp>

#include <algorithm>
#include <cmath>
#include <limits>

namespace dgmpm {

TimeStepControl::TimeStepControl(const scene::TimeSpec& time, bool particles_move)
    : automatic_(time.courant_auto), courant_(time.courant), safety_(time.safety),
      quantum_(particles_move ? moving_position_quantum : fixed_position_quantum),
      scheme_(time.integrator), criterion_(time.criterion) {}

double TimeStepControl::quantise_position(double xi, double quantum) {
  const double d = std::min(xi, 1.0 - xi);              // distance to the nearest node
  if (!(d > 0.0)) return xi;                            // on a node (or not a number): as it is
  if (d < 0.5 * quantum) return xi <= 0.5 ? 0.0 : 1.0;  // below the resolution: on the node
  int exponent = 0;
  std::frexp(d, &exponent);  // d in [2^(exponent - 1), 2^exponent)
  const double step = std::min(quantum, std::ldexp(1.0, exponent - 1 - node_distance_bits));
  const double rounded = std::round(d / step) * step;  // >= 2^8 steps: never 0
  return xi <= 0.5 ? rounded : 1.0 - rounded;
}

void TimeStepControl::fill_key(const Disc& disc, const BarParticles& particles, int c) {
  entries_.clear();
  for (int e = disc.cell_begin(c); e < disc.cell_end(c); ++e) {
    const int p = disc.entry_particle(e);
    entries_.emplace_back(quantise_position(disc.particle_local(p)[0], quantum_),
                          particles.mass[p]);
  }
  // A lone particle's one-step map does not depend on where it sits (lib's update reduces to the
  // upwind finite-volume one; tests/stability_von_neumann.cpp checks C* = 1 from xi = 0 to 1 and
  // next to the nodes): all such cells share the key of the first one analysed.
  if (entries_.size() == 1) entries_.front().first = 0.5;
  std::sort(entries_.begin(), entries_.end());
  const double unit = entries_.front().second;  // the analysis rescales masses to a full cell
  key_.clear();
  for (const auto& entry : entries_) key_.push_back(entry.first);
  for (const auto& entry : entries_) key_.push_back(entry.second / unit);
}

stability::CellLayout TimeStepControl::key_layout() const {
  const auto n = static_cast<std::ptrdiff_t>(key_.size() / 2);
  return {std::vector<double>(key_.begin(), key_.begin() + n),
          std::vector<double>(key_.begin() + n, key_.end())};
}

stability::CellLayout TimeStepControl::layout_of(const Disc& disc, const BarParticles& particles,
                                                 int c) {
  fill_key(disc, particles, c);
  return key_layout();
}

double TimeStepControl::cell_courant(const Disc& disc, const BarParticles& particles, int c,
                                     double cell_volume) {
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

TimeStepControl::Limit TimeStepControl::smallest_admissible(const Disc& disc,
                                                            const BarParticles& particles,
                                                            double cell_volume) {
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

double TimeStepControl::time_step(const Disc& disc, const BarParticles& particles, double h) {
  // 1D: h is the cell's volume.
  double dt = std::numeric_limits<double>::infinity();
  for (int c = 0; c < disc.num_cells(); ++c) {
    if (!disc.occupied(c)) continue;
    const double speed = disc.cell_material(c).wave_speed();
    const double cs = automatic_ ? safety_ * cell_courant(disc, particles, c, h) : courant_;
    dt = std::min(dt, cs * h / speed);
  }
  return dt;
}

}  // namespace dgmpm
