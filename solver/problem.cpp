#include "solver/problem.hpp"

#include <dgmpm/exact/elastic_bar.hpp>

#include <algorithm>
#include <cmath>
#include <limits>
#include <numeric>

namespace dgmpm {

namespace {

ElasticBar::Material material_of(const scene::MaterialSpec& m, ElasticBar*) {
  return {m.young, m.density};
}
PlaneStrain::Material material_of(const scene::MaterialSpec& m, PlaneStrain*) {
  return {m.young, m.poisson, m.density};
}

ElasticBar::State initial_state(const scene::BodySpec& b, const ElasticBar::Material& m) {
  return ElasticBar::specific(b.stress[0], b.velocity[0], m);
}
PlaneStrain::State initial_state(const scene::BodySpec& b, const PlaneStrain::Material& m) {
  return PlaneStrain::specific(Eigen::Vector3d(b.stress[0], b.stress[1], b.stress[2]),
                               PlaneStrain::Vec(b.velocity[0], b.velocity[1]), m);
}

template <int Dim>
BoundarySide<Dim> side_of(const std::vector<scene::BoundarySpec>& specs, int axis) {
  BoundarySide<Dim> side;
  for (const auto& spec : specs) {
    BoundarySegment<Dim> segment;
    segment.condition.kind = spec.kind;
    segment.condition.value.times = spec.times;
    for (std::size_t k = 0; k < spec.times.size(); ++k)
      segment.condition.value.values.push_back(
          Eigen::Map<const Eigen::Matrix<double, Dim, 1>>(spec.values.data() + k * Dim));
    if (spec.has_range) {
      const int t = 1 - axis;  // 2D: the side's tangential axis
      segment.lo[t] = spec.range_lo;
      segment.hi[t] = spec.range_hi;
    }
    side.segments.push_back(segment);
  }
  return side;
}

void set_exact(const scene::Scene& scene, Problem<ElasticBar>& problem) {
  if (!scene.exact) return;
  const auto fail = [&](const std::string& why) {
    return scene::SceneError(scene.source + ": exact: value \"bar\" cannot be used here: " + why);
  };
  const int material = scene.bodies.front().material;
  std::vector<exact::Segment> segments;
  for (const auto& b : scene.bodies) {
    if (b.material != material) throw fail("the exact bar solution needs a single material");
    segments.push_back({b.box_min[0], b.box_max[0], b.stress[0], b.velocity[0]});
  }
  std::sort(segments.begin(), segments.end(),
            [](const auto& a, const auto& b) { return a.x0 < b.x0; });
  for (std::size_t k = 1; k < segments.size(); ++k)
    if (segments[k].x0 != segments[k - 1].x1)
      throw fail("the bodies must form one bar without gaps");
  const double a = segments.front().x0, b = segments.back().x1;
  const auto& m = problem.materials[material];
  const Grid<1>& g = problem.grid;
  std::optional<exact::ElasticBarSolution> solution;
  if (g.periodic[0]) {
    if (a != g.origin[0] || b != g.upper(0))
      throw fail("on a periodic grid the bar must fill the grid");
    solution = exact::ElasticBarSolution::periodic(a, b, m.young, m.density, segments);
  } else {
    // A bar end inside the grid faces void cells: a free surface.
    const auto end = [&](int side, bool at_grid) {
      const auto& segs = problem.boundaries[0][side].segments;
      return at_grid && !segs.empty() ? segs.front().condition : BoundaryCondition<1>{};
    };
    solution = exact::ElasticBarSolution(a, b, m.young, m.density, segments,
                                         end(0, a == g.origin[0]), end(1, b == g.upper(0)));
  }
  problem.exact_impedance = solution->impedance();
  problem.exact = [s = *solution](const Eigen::Matrix<double, 1, 1>& x, double t) {
    return ElasticBar::State(s.stress(x[0], t), s.velocity(x[0], t));
  };
}

void set_exact(const scene::Scene& scene, Problem<PlaneStrain>&) {
  if (scene.exact)
    throw scene::SceneError(scene.source + ": exact: value \"" + *scene.exact +
                            "\" cannot be used in 2D; allowed: no exact key");
}

template <class Physics>
void add_body_particles(const scene::Scene& scene, std::size_t body_index,
                        const Grid<Physics::dim>& grid, const typename Physics::Material& mat,
                        Particles<Physics::dim, Physics::n_comp>& particles) {
  constexpr int dim = Physics::dim;
  const scene::BodySpec& body = scene.bodies[body_index];
  const double density = scene.materials[body.material].density;
  const std::vector<double>& w = body.masses_in_cell;
  const double wsum = std::accumulate(w.begin(), w.end(), 0.0);
  const auto state = initial_state(body, mat);
  const std::vector<scene::Seed> seeds = scene::body_seeds(scene, body_index);
  const int first = particles.size(), n = first + static_cast<int>(seeds.size());
  particles.position.conservativeResize(dim, n);
  particles.mass.conservativeResize(n);
  particles.volume.conservativeResize(n);
  particles.state.conservativeResize(Physics::n_comp, n);
  for (int p = first; p < n; ++p) {
    const scene::Seed& seed = seeds[p - first];
    for (int a = 0; a < dim; ++a) particles.position(a, p) = seed.x[a];
    particles.volume[p] = grid.cell_volume() * w[seed.local] / wsum;
    particles.mass[p] = density * particles.volume[p];
    particles.state.col(p) = state;
    particles.material.push_back(body.material);
    particles.id.push_back(p);
  }
}

}  // namespace

template <class Physics>
Problem<Physics> make_problem(const scene::Scene& scene) {
  constexpr int dim = Physics::dim;
  if (scene.dimension != dim)
    throw scene::SceneError(scene.source + ": dimension: value " +
                            std::to_string(scene.dimension) + " does not fit a " +
                            std::to_string(dim) + "D problem");
  Problem<Physics> p;
  for (int a = 0; a < dim; ++a) {
    p.grid.origin[a] = scene.grid.origin[a];
    p.grid.cell_size[a] = scene.grid.cell_size[a];
    p.grid.cells[a] = scene.grid.cells[a];
    p.grid.periodic[a] = scene.grid.periodic[a];
    for (int side = 0; side < 2; ++side)
      p.boundaries[a][side] = side_of<dim>(scene.boundaries[a][side], a);
  }
  for (const auto& m : scene.materials)
    p.materials.push_back(material_of(m, static_cast<Physics*>(nullptr)));
  p.particles.resize(0);
  for (std::size_t b = 0; b < scene.bodies.size(); ++b)
    add_body_particles<Physics>(scene, b, p.grid, p.materials[scene.bodies[b].material],
                                p.particles);
  set_exact(scene, p);
  return p;
}

template Problem<ElasticBar> make_problem<ElasticBar>(const scene::Scene&);
template Problem<PlaneStrain> make_problem<PlaneStrain>(const scene::Scene&);

}  // namespace dgmpm
