#include "solver/problem.hpp"

#include <algorithm>
#include <cmath>
#include <numeric>

namespace dgmpm {

namespace {

BoundaryCondition<1> boundary_of(const scene::BoundarySpec& spec) {
  BoundaryCondition<1> bc;
  bc.kind = spec.kind;
  bc.value.times = spec.times;
  for (double v : spec.values) bc.value.values.push_back(Eigen::Matrix<double, 1, 1>(v));
  return bc;
}

std::optional<exact::ElasticBarSolution> make_exact(const scene::Scene& scene,
                                                    const BarProblem& problem) {
  if (!scene.exact) return std::nullopt;
  const auto fail = [&](const std::string& why) {
    return scene::SceneError(scene.source + ": exact: value \"bar\" cannot be used here: " + why);
  };
  const int material = scene.bodies.front().material;
  std::vector<exact::Segment> segments;
  for (const auto& b : scene.bodies) {
    if (b.material != material) throw fail("the exact bar solution needs a single material");
    const double sigma = b.stress.empty() ? 0.0 : b.stress[0];
    const double v = b.velocity.empty() ? 0.0 : b.velocity[0];
    segments.push_back({b.box_min[0], b.box_max[0], sigma, v});
  }
  std::sort(segments.begin(), segments.end(),
            [](const auto& a, const auto& b) { return a.x0 < b.x0; });
  for (std::size_t k = 1; k < segments.size(); ++k)
    if (segments[k].x0 != segments[k - 1].x1)
      throw fail("the bodies must form one bar without gaps");
  const double a = segments.front().x0, b = segments.back().x1;
  const auto& m = problem.materials[material];
  const Grid<1>& g = problem.grid;
  if (g.periodic[0]) {
    if (a != g.origin[0] || b != g.upper(0))
      throw fail("on a periodic grid the bar must fill the grid");
    return exact::ElasticBarSolution::periodic(a, b, m.young, m.density, segments);
  }
  // A bar end inside the grid faces void cells: a free surface.
  const BoundaryCondition<1> left =
      a == g.origin[0] ? problem.boundaries[0][0] : BoundaryCondition<1>{};
  const BoundaryCondition<1> right =
      b == g.upper(0) ? problem.boundaries[0][1] : BoundaryCondition<1>{};
  return exact::ElasticBarSolution(a, b, m.young, m.density, segments, left, right);
}

}  // namespace

void add_body_particles(const scene::Scene& scene, std::size_t body_index, const Grid<1>& grid,
                        Particles<1, ElasticBar::n_comp>& particles) {
  const scene::BodySpec& body = scene.bodies[body_index];
  const double density = scene.materials[body.material].density;
  std::vector<double> w = body.masses_in_cell;
  if (w.empty()) w.assign(body.positions_in_cell.size(), 1.0);
  const double wsum = std::accumulate(w.begin(), w.end(), 0.0);
  const ElasticBar::Material mat{1.0, density};
  const double sigma = body.stress.empty() ? 0.0 : body.stress[0];
  const double v = body.velocity.empty() ? 0.0 : body.velocity[0];
  const std::vector<scene::Seed> seeds = scene::body_seeds(scene, body_index);
  const int first = particles.size(), n = first + static_cast<int>(seeds.size());
  particles.position.conservativeResize(1, n);
  particles.mass.conservativeResize(n);
  particles.volume.conservativeResize(n);
  particles.state.conservativeResize(ElasticBar::n_comp, n);
  for (int p = first; p < n; ++p) {
    const scene::Seed& seed = seeds[p - first];
    particles.position(0, p) = seed.x[0];
    particles.volume[p] = grid.cell_size[0] * w[seed.local[0]] / wsum;
    particles.mass[p] = density * particles.volume[p];
    particles.state.col(p) = ElasticBar::specific(sigma, v, mat);
    particles.material.push_back(body.material);
    particles.id.push_back(p);
  }
}

double BarProblem::max_wave_speed() const {
  double c = 0;
  for (int p = 0; p < particles.size(); ++p)
    c = std::max(c, materials[particles.material[p]].wave_speed());
  return c;
}

BarProblem make_bar_problem(const scene::Scene& scene) {
  BarProblem p;
  p.grid.origin[0] = scene.grid.origin[0];
  p.grid.cell_size[0] = scene.grid.cell_size[0];
  p.grid.cells[0] = scene.grid.cells[0];
  p.grid.periodic[0] = scene.grid.periodic;
  for (int side = 0; side < 2; ++side)
    p.boundaries[0][side] = boundary_of(scene.boundaries[0][side]);
  for (const auto& m : scene.materials) {
    p.materials.push_back({m.young, m.density});
    p.poisson.push_back(m.poisson);
  }
  p.particles.resize(0);
  for (std::size_t b = 0; b < scene.bodies.size(); ++b)
    add_body_particles(scene, b, p.grid, p.particles);
  p.exact = make_exact(scene, p);
  return p;
}

}  // namespace dgmpm
