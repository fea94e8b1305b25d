#pragma once
// A periodic grid of identical cells, each holding the same layout, stepped by lib's own stepper
// (docs/method.md, "Stability"): the model problem of the von Neumann analysis, in 1D or 2D.
// Units (AnalysisSetting): min(dx, dy) = 1 and a unit wave speed (advection speed 1 in 1D,
// elastic bar E = rho = 1, plane strain with c_p = 1), so that dt = C for elasticity.

#include "stability/layout.hpp"
#include "stability/options.hpp"

#include <dgmpm/grid.hpp>
#include <dgmpm/particles.hpp>
#include <dgmpm/physics/advection.hpp>
#include <dgmpm/physics/elastic_bar.hpp>
#include <dgmpm/physics/plane_strain.hpp>
#include <dgmpm/stepper.hpp>

#include <algorithm>
#include <array>
#include <cmath>
#include <optional>
#include <vector>

namespace dgmpm::stability {

// The unit material of each physics for a setting.
inline Advection<1>::Material unit_material(const AnalysisSetting&, Advection<1>*) {
  return {};
}
inline ElasticBar::Material unit_material(const AnalysisSetting&, ElasticBar*) {
  return {};
}
inline Advection<2>::Material unit_material(const AnalysisSetting& s, Advection<2>*) {
  Advection<2>::Material m;
  m.speed << s.speed_x, s.speed_y;
  return m;
}
// c_p = 1: lambda + 2 mu = 1 and, in plane strain, lambda / (lambda + 2 mu) = nu / (1 - nu).
inline PlaneStrain::Material unit_material(const AnalysisSetting& s, PlaneStrain*) {
  const double nu = s.poisson;
  return PlaneStrain::Material::from_lame(nu / (1 - nu), (1 - 2 * nu) / (2 * (1 - nu)), 1.0);
}
template <class Physics>
typename Physics::Material unit_material(const AnalysisSetting& s = {}) {
  return unit_material(s, static_cast<Physics*>(nullptr));
}

template <int dim>
std::array<int, dim> filled(int n) {
  std::array<int, dim> a;
  a.fill(n);
  return a;
}

template <class Physics>
class PeriodicCells {
 public:
  static constexpr int dim = Physics::dim;
  static constexpr int ncomp = Physics::n_comp;
  using Field = typename DGOperator<Physics>::ParticleField;

  // Particle p = e * N + k is particle k of the layout in cell e (cells numbered x fastest). One
  // on a cell's upper face (xi = 1) is placed at xi = 0 of the same cell instead: lib files a
  // particle on a face in the cell above it, so the periodic configuration is the same, and the
  // labelling keeps the particle with the cell that holds it (the shortest stencil).
  PeriodicCells(const CellLayout& layout, int cells, const AnalysisSetting& setting = {})
      : PeriodicCells(layout, filled<dim>(cells), setting) {}
  // Cells per axis (a long-wave mode along one axis needs many cells there only).
  PeriodicCells(const CellLayout& layout, const std::array<int, dim>& cells,
                const AnalysisSetting& setting = {})
      : n_(layout.size()), setting_(setting) {
    validate(layout);
    for (int a = 0; a < dim; ++a) {
      grid_.cells[a] = cells[a];
      grid_.periodic[a] = true;
    }
    if constexpr (dim == 2)
      grid_.cell_size << std::max(1.0, setting.aspect), std::max(1.0, 1.0 / setting.aspect);
    const int nc = grid_.num_cells();
    particles_.resize(nc * n_);
    for (int e = 0; e < nc; ++e) {
      const auto k = grid_.unflatten(e);
      for (int j = 0; j < n_; ++j) {
        const int p = e * n_ + j;
        for (int a = 0; a < dim; ++a) {
          const double xi = layout.position(j, a);
          particles_.position(a, p) = (k[a] + (xi == 1.0 ? 0.0 : xi)) * grid_.cell_size[a];
        }
        particles_.mass[p] = layout.mass_fraction(j) * grid_.cell_volume();  // rho = 1
        particles_.volume[p] = particles_.mass[p];
        particles_.material[p] = 0;
        particles_.id[p] = p;
      }
    }
    particles_.state.setZero();
    materials_.push_back(unit_material<Physics>(setting));
    stepper_.emplace(grid_, boundaries_,
                     StepperOptions{setting.time, setting.flux, setting.formulation});
    stepper_->rebuild(particles_, materials_);
  }
  PeriodicCells(const PeriodicCells&) = delete;  // the stepper refers to the members
  PeriodicCells& operator=(const PeriodicCells&) = delete;

  int cells() const { return grid_.cells[0]; }  // along x
  int cell_index(const typename Grid<dim>::Index& k) const { return grid_.flatten(k); }
  // Smallest share of a cell's mass that one of its nodes holds, nodes that lib folds as massless
  // aside (every cell is the same: cell 0 speaks for all).
  double smallest_node_share() const {
    const auto& disc = stepper_->discretisation();
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

  // The time step of Courant number C (see AnalysisSetting).
  double time_step(double courant) const {
    if constexpr (std::is_same_v<Physics, Advection<2>>)
      return courant / std::max(std::abs(setting_.speed_x) / grid_.cell_size[0],
                                std::abs(setting_.speed_y) / grid_.cell_size[1]);
    return courant;
  }

  // One step of lib's stepper at Courant number C.
  void step(double courant) {
    stepper_->step(particles_.state, particles_.mass, 0.0, time_step(courant));
  }

 private:
  int n_;
  AnalysisSetting setting_;
  Grid<dim> grid_;
  Particles<dim, ncomp> particles_;
  std::vector<typename Physics::Material> materials_;
  Boundaries<dim> boundaries_{};  // unused: every axis is periodic
  std::optional<Stepper<Physics>> stepper_;
};

}  // namespace dgmpm::stability
