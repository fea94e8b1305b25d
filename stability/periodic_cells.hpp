#pragma once
// A periodic 1D grid of identical cells, each holding the same layout, stepped by lib's own
// integrators: the model problem of the von Neumann analysis (method.md 5). Units: dx = 1 and a
// unit wave speed (advection speed 1; elastic bar E = rho = 1, so Z = 1), hence dt = C.

#include "stability/layout.hpp"
#include "stability/options.hpp"

#include <dgmpm/grid.hpp>
#include <dgmpm/particles.hpp>
#include <dgmpm/physics/advection.hpp>
#include <dgmpm/physics/elastic_bar.hpp>
#include <dgmpm/stepper.hpp>

#include <algorithm>
#include <optional>
#include <vector>

namespace dgmpm::stability {

template <class Physics>
typename Physics::Material unit_material() {
  return typename Physics::Material{};  // both physics default to unit speed, E = rho = 1
}

template <class Physics>
class PeriodicCells {
 public:
  static constexpr int ncomp = Physics::n_comp;
  using Field = typename DGOperator<Physics>::ParticleField;

  // Particle p = e * N + k is particle k of the layout in cell e. One on the cell's upper face
  // (xi = 1) is placed at xi = 0 of the same cell instead: lib files a particle on a face in the
  // cell above it, so the periodic configuration is the same, and the labelling keeps the
  // particle with the cell that holds it (the shortest stencil).
  PeriodicCells(const CellLayout& layout, int cells) : n_(layout.size()) {
    validate(layout);
    grid_.cells = {cells};
    grid_.periodic = {true};
    particles_.resize(cells * n_);
    for (int e = 0; e < cells; ++e)
      for (int k = 0; k < n_; ++k) {
        const int p = e * n_ + k;
        const double xi = layout.positions[k];
        particles_.position(0, p) = e + (xi == 1.0 ? 0.0 : xi);
        particles_.mass[p] = layout.mass_fraction(k);  // rho dx = 1 per cell
        particles_.volume[p] = particles_.mass[p];
        particles_.material[p] = 0;
        particles_.id[p] = p;
      }
    particles_.state.setZero();
    materials_.push_back(unit_material<Physics>());
    for (TimeScheme scheme : {TimeScheme::euler, TimeScheme::rk2}) {
      auto& s = steppers_[static_cast<int>(scheme)];
      s.emplace(grid_, boundaries_, StepperOptions{scheme});
      s->rebuild(particles_, materials_);
    }
  }
  PeriodicCells(const PeriodicCells&) = delete;  // the operator refers to the members
  PeriodicCells& operator=(const PeriodicCells&) = delete;

  int cells() const { return grid_.cells[0]; }
  // Smallest share of a cell's mass that one of its nodes holds, nodes that lib folds as massless
  // aside (every cell is the same: cell 0 speaks for all).
  double smallest_node_share() const {
    const auto& disc = steppers_[0]->discretisation();
    const double cell = disc.cell_mass(0);
    double share = 1.0;
    for (int a = 0; a < Discretisation<Physics>::npc; ++a) {
      const double s = disc.node_mass(a) / cell;
      if (s > Discretisation<Physics>::massless_share) share = std::min(share, s);
    }
    return share;
  }
  int particles_per_cell() const { return n_; }
  int num_particles() const { return particles_.size(); }
  Field& state() { return particles_.state; }
  const Field& state() const { return particles_.state; }

  // One step of lib's integrator at Courant number `courant` (dt = courant here).
  void step(TimeScheme scheme, double courant) {
    steppers_[static_cast<int>(scheme)]->step(particles_.state, particles_.mass, 0.0, courant);
  }

 private:
  int n_;
  Grid<1> grid_;
  Particles<1, ncomp> particles_;
  std::vector<typename Physics::Material> materials_;
  Boundaries<1> boundaries_{};                   // unused: every axis is periodic
  std::optional<Stepper<Physics>> steppers_[2];  // [TimeScheme]
};

}  // namespace dgmpm::stability
