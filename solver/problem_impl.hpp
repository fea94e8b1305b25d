#pragma once
// make_problem's definition: what a scene's materials and bodies mean for a physics. problem.cpp
// instantiates it for the shipped physics; a physics defined elsewhere (a test's) includes this
// header. A physics finds its material and initial state below by overload on a pointer to it,
// so one derived from a shipped physics (same Material and State) reads the scene as its base
// does; one of its own declares its own overloads beside it.

#include "solver/problem.hpp"

#include <algorithm>
#include <numeric>
#include <string>
#include <vector>

namespace dgmpm {

// The material of a scene's description, for each physics.
inline ElasticBar::Material material_of(const scene::MaterialSpec& m, ElasticBar*) {
  return {m.young, m.density};
}
inline ElastoPlasticBar::Material material_of(const scene::MaterialSpec& m, ElastoPlasticBar*) {
  return {m.young, m.density, m.flow()};  // linear_elastic: an infinite yield stress
}
inline PlaneStrainPlastic::Material material_of(const scene::MaterialSpec& m, PlaneStrainPlastic*) {
  return {m.young, m.poisson, m.density, m.flow()};
}
inline UniaxialStrainPlastic::Material material_of(const scene::MaterialSpec& m,
                                                   UniaxialStrainPlastic*) {
  return {m.young, m.poisson, m.density, m.flow()};
}
inline PlaneStrain::Material material_of(const scene::MaterialSpec& m, PlaneStrain*) {
  return {m.young, m.poisson, m.density};
}
template <class Law>
typename FiniteStrainBar<Law>::Material material_of(const scene::MaterialSpec& m,
                                                    FiniteStrainBar<Law>*) {
  return {m.young, m.poisson, m.density};
}
template <class Law>
typename FiniteStrainPlane<Law>::Material material_of(const scene::MaterialSpec& m,
                                                      FiniteStrainPlane<Law>*) {
  return {m.young, m.poisson, m.density};
}

// The initial specific state of a body's particles (the tag picks the physics' own, if any).
inline ElasticBar::State initial_state(const scene::BodySpec& b, const ElasticBar::Material& m,
                                       const void*) {
  return ElasticBar::specific(b.stress[0], b.velocity[0], m);
}
inline PlaneStrain::State initial_state(const scene::BodySpec& b, const PlaneStrain::Material& m,
                                        const void*) {
  return PlaneStrain::specific(Eigen::Vector3d(b.stress[0], b.stress[1], b.stress[2]),
                               PlaneStrain::Vec(b.velocity[0], b.velocity[1]), m);
}

// Unstrained (F = 1) unless the body gives its deformation gradient.
template <class Law>
typename FiniteStrainBar<Law>::State initial_state(const scene::BodySpec& b,
                                                   const typename FiniteStrainBar<Law>::Material& m,
                                                   FiniteStrainBar<Law>*) {
  const double f = b.deformation_gradient.empty() ? 1.0 : b.deformation_gradient[0];
  return FiniteStrainBar<Law>::specific(f, b.velocity[0], m);
}
// deformation_gradient: [F_xx, F_xy, F_yx, F_yy].
template <class Law>
typename FiniteStrainPlane<Law>::State
initial_state(const scene::BodySpec& b, const typename FiniteStrainPlane<Law>::Material& m,
              FiniteStrainPlane<Law>*) {
  Eigen::Matrix2d f = Eigen::Matrix2d::Identity();
  if (!b.deformation_gradient.empty())
    f << b.deformation_gradient[0], b.deformation_gradient[1], b.deformation_gradient[2],
        b.deformation_gradient[3];
  return FiniteStrainPlane<Law>::specific(f, Eigen::Vector2d(b.velocity[0], b.velocity[1]), m);
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
    if constexpr (Dim == 2) {
      if (spec.has_range) {
        const int t = 1 - axis;  // the side's tangential axis
        segment.lo[t] = spec.range_lo;
        segment.hi[t] = spec.range_hi;
      }
    }
    side.segments.push_back(segment);
  }
  return side;
}

// The exact solution or initial plane wave the scene asks for (problem.cpp): only the elastic
// physics have them.
void set_exact(const scene::Scene& scene, Problem<ElasticBar>& problem);
void set_exact(const scene::Scene& scene, Problem<PlaneStrain>& problem);
// Any other physics: refused (with a reason of their own for the plastic ones; the parser refuses
// them with finite strain).
void set_exact(const scene::Scene& scene, Problem<ElastoPlasticBar>& problem);
void set_exact(const scene::Scene& scene, Problem<UniaxialStrainPlastic>& problem);
void set_exact(const scene::Scene& scene, Problem<PlaneStrainPlastic>& problem);
template <class Physics>
void set_exact(const scene::Scene& scene, Problem<Physics>&) {
  if (scene.exact || scene.plane_wave)
    throw scene::SceneError(scene.source + ": " + (scene.plane_wave ? "plane_wave" : "exact") +
                            ": cannot be used here: no exact solution is known to this physics");
}

// Refuses, before anything is allocated, a scene that would not fit in memory (problem.cpp).
void check_memory(const scene::Scene& scene);

template <class Physics>
void add_body_particles(const scene::Scene& scene, std::size_t body_index,
                        const Grid<Physics::dim>& grid, const typename Physics::Material& mat,
                        ParticlesOf<Physics>& particles) {
  constexpr int dim = Physics::dim;
  const scene::BodySpec& body = scene.bodies[body_index];
  const double density = scene.materials[body.material].density;
  // Weights relative to the largest: 1e308 each would overflow their sum.
  std::vector<double> w = body.masses_in_cell;
  const double largest = *std::max_element(w.begin(), w.end());
  for (double& x : w) x /= largest;
  const double wsum = std::accumulate(w.begin(), w.end(), 0.0);
  const auto state = initial_state(body, mat, static_cast<Physics*>(nullptr));
  const std::vector<scene::Seed> seeds = scene::body_seeds(scene, body_index);
  const int first = particles.size(), n = first + static_cast<int>(seeds.size());
  particles.resize(n, true);
  for (int p = first; p < n; ++p) {
    const scene::Seed& seed = seeds[p - first];
    for (int a = 0; a < dim; ++a) particles.position(a, p) = seed.x[a];
    particles.volume[p] = grid.cell_volume() * w[seed.local] / wsum;
    particles.mass[p] = density * particles.volume[p];
    particles.state.col(p) = state;
    particles.internal.col(p).setZero();  // no plastic strain or hardening yet
    particles.material[p] = body.material;
    particles.id[p] = p;
  }
}

template <class Physics>
Problem<Physics> make_problem(const scene::Scene& scene) {
  constexpr int dim = Physics::dim;
  if (scene.dimension != dim)
    throw scene::SceneError(scene.source + ": dimension: value " + std::to_string(scene.dimension) +
                            " does not fit a " + std::to_string(dim) + "D problem");
  check_memory(scene);
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

}  // namespace dgmpm
