#pragma once
// Problem description: what a scene means for the discretisation: grid, boundary conditions,
// materials, generated particles and, when asked for, the exact solution.

#include "solver/scene.hpp"

#include <dgmpm/boundary.hpp>
#include <dgmpm/exact/elastic_bar.hpp>
#include <dgmpm/grid.hpp>
#include <dgmpm/particles.hpp>
#include <dgmpm/physics/elastic_bar.hpp>

#include <optional>
#include <vector>

namespace dgmpm {

struct BarProblem {
  using Physics = ElasticBar;
  static constexpr int dim = 1;
  Grid<1> grid;
  Boundaries<1> boundaries;
  std::vector<ElasticBar::Material> materials;
  std::vector<double> poisson;  // per material, unused in 1D but kept for reports
  Particles<1, ElasticBar::n_comp> particles;
  std::optional<exact::ElasticBarSolution> exact;

  // Largest wave speed among the materials the particles carry.
  double max_wave_speed() const;
};

// Throws scene::SceneError when the scene's pieces do not fit together (e.g. an exact solution
// asked for a bar of several materials).
BarProblem make_bar_problem(const scene::Scene& scene);

// Particles of one body, at the scene's seeds (scene::body_seeds: the body's cell layout kept
// where it falls in the box). Each carries its share of rho * cell volume by masses_in_cell.
void add_body_particles(const scene::Scene& scene, std::size_t body_index, const Grid<1>& grid,
                        Particles<1, ElasticBar::n_comp>& particles);

}  // namespace dgmpm
