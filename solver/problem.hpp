#pragma once
// Problem description: what a scene means for the discretisation: grid, boundary conditions,
// materials, generated particles and, when asked for, the exact solution. One template for every
// physics; the physics is chosen from the scene's dimension in one place (simulation.hpp).

#include "solver/scene.hpp"

#include <dgmpm/boundary.hpp>
#include <dgmpm/grid.hpp>
#include <dgmpm/particles.hpp>
#include <dgmpm/physics/contract.hpp>
#include <dgmpm/physics/elastic_bar.hpp>
#include <dgmpm/physics/elastoplastic_bar.hpp>
#include <dgmpm/physics/finite_strain_bar.hpp>
#include <dgmpm/physics/finite_strain_plane.hpp>
#include <dgmpm/physics/plane_strain.hpp>
#include <dgmpm/physics/plane_strain_plastic.hpp>
#include <dgmpm/physics/uniaxial_strain_plastic.hpp>

#include <cmath>
#include <functional>
#include <string>
#include <type_traits>
#include <variant>
#include <vector>

namespace dgmpm {

template <class Physics>
struct Problem {
  static constexpr int dim = Physics::dim;
  using State = typename Physics::State;
  using Vec = Eigen::Matrix<double, dim, 1>;
  Grid<dim> grid;
  Boundaries<dim> boundaries;
  std::vector<typename Physics::Material> materials;
  ParticlesOf<Physics> particles;
  // Exact solution, physical state (sigma, v) at material point x0 and time t; empty if none.
  std::function<State(const Vec& x0, double t)> exact;
  // The impedance that relates the exact solution's stress and velocity scales.
  double exact_impedance = 1.0;

  // Largest wave speed among the materials the particles carry (at the particles' states where
  // the speeds change with the state).
  double max_wave_speed() const {
    double c = 0;
    for (int p = 0; p < particles.size(); ++p) {
      const auto& m = materials[particles.material[p]];
      if constexpr (physics::StateDependentSpeed<Physics>) {
        const double cp = Physics::state_wave_speed(particles.state.col(p), m);
        if (std::isnan(cp)) return cp;  // outside the hyperbolic range
        c = std::max(c, cp);
      } else {
        c = std::max(c, Physics::max_wave_speed(m));
      }
    }
    return c;
  }
};

using BarProblem = Problem<ElasticBar>;

// Throws scene::SceneError when the scene's pieces do not fit together (e.g. an exact solution
// asked for a bar of several materials) or its dimension is not the physics'.
template <class Physics>
Problem<Physics> make_problem(const scene::Scene& scene);

// The one place where a scene's dimension, strain state and material models pick its physics:
// returns f(std::type_identity<Physics>{}) for the scene's physics (1D: ElasticBar, or
// ElastoPlasticBar when a material yields, UniaxialStrainPlastic for "strain":
// "uniaxial_strain", FiniteStrainBar with the scene's hyperelastic law; 2D: PlaneStrain, or
// PlaneStrainPlastic when a material yields, FiniteStrainPlane with the scene's hyperelastic
// law). The first material's model stands for all: the parser has refused scenes that mix
// finite and small strain, or two laws.
template <class F>
decltype(auto) with_physics(const scene::Scene& scene, F&& f) {
  bool plastic = false;
  for (const auto& m : scene.materials) plastic = plastic || m.plastic();
  const scene::MaterialModel& model = scene.materials.front().model;
  const bool svk = std::holds_alternative<scene::Hyperelastic<SaintVenantKirchhoff>>(model);
  const bool nh = std::holds_alternative<scene::Hyperelastic<NeoHookean>>(model);
  switch (scene.dimension) {
    case 1:
      if (svk) return f(std::type_identity<FiniteStrainBar<SaintVenantKirchhoff>>{});
      if (nh) return f(std::type_identity<FiniteStrainBar<NeoHookean>>{});
      if (scene.uniaxial_strain) return f(std::type_identity<UniaxialStrainPlastic>{});
      if (plastic) return f(std::type_identity<ElastoPlasticBar>{});
      return f(std::type_identity<ElasticBar>{});
    case 2:
      if (svk) return f(std::type_identity<FiniteStrainPlane<SaintVenantKirchhoff>>{});
      if (nh) return f(std::type_identity<FiniteStrainPlane<NeoHookean>>{});
      if (plastic) return f(std::type_identity<PlaneStrainPlastic>{});
      return f(std::type_identity<PlaneStrain>{});
  }
  throw scene::SceneError(scene.source + ": dimension: value " + std::to_string(scene.dimension) +
                          " is not implemented; allowed: 1 or 2");
}

inline BarProblem make_bar_problem(const scene::Scene& scene) {
  return make_problem<ElasticBar>(scene);
}

}  // namespace dgmpm
