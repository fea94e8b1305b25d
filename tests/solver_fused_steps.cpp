// Steps are fused: one pass over the cells per stage projects each cell (a few layers of cells
// ahead), computes CTU's faces (a layer ahead), each cell's whole residual and update (and, for
// Euler and RK2's last stage, its particles and their particle step). The unfused definition is
// lib's ReferenceStepper, the composition of four stages over whole arrays, project -> residual
// (volume terms, then face by face) -> update -> interpolate, for Euler and Heun's RK2: both must
// give the same particle states and internal variables to the last bit, on 1D and 2D scenes with
// boundaries (traction, free, roller), periodic axes, void cells, massless and near-empty nodes,
// over-full and empty cells inside a body, two materials, plastic flow (a return at each
// particle), finite strain, with DCU and CTU fluxes (threads: tests/solver_threads.cpp).
#define BOOST_TEST_MODULE solver_fused_steps
#include <boost/test/unit_test.hpp>

#include "common/disturb.hpp"
#include "common/loaded_scenes.hpp"
#include "solver/problem.hpp"
#include "solver/scene.hpp"
#include "solver/simulation.hpp"

#include <dgmpm/reference_stepper.hpp>

#include <nlohmann/json.hpp>

#include <string>

using namespace dgmpm;
using nlohmann::json;

namespace {

json bar(const std::string& integrator) {
  return test::loaded_bar(70, 0.1, integrator, false);
}

json plate(const std::string& integrator, const std::string& flux = "dcu") {
  return test::loaded_plate(20, 14, 0.25, 2, flux, integrator, false);
}

// The largest difference between the fused and the reference steps' particle states and internal
// variables over `steps` steps, relative to the largest state.
template <class Physics>
double largest_difference(const json& doc, int steps) {
  const scene::Scene scene = scene::parse_scene(doc, "fused");
  Problem<Physics> problem = make_problem<Physics>(scene);
  test::disturb(problem.particles, problem.grid);
  const StepperOptions options = stepper_options(scene);
  Stepper<Physics> stepper(problem.grid, problem.boundaries, options);
  stepper.rebuild(problem.particles, problem.materials);
  const auto& disc = stepper.discretisation();
  BOOST_TEST_REQUIRE(disc.has_massless_nodes());
  BOOST_TEST_REQUIRE(disc.has_near_empty_nodes());  // RK2 damps their first stage
  int empty = 0;
  for (int c = 0; c < disc.num_cells(); ++c) empty += !disc.occupied(c);
  BOOST_TEST_REQUIRE(empty > 0);

  const double dt = 0.4 * problem.grid.cell_size.minCoeff() / problem.max_wave_speed();
  ParticlesOf<Physics> fused = problem.particles, unfused = fused;
  const ReferenceStepper<Physics> reference(stepper);
  double worst = 0.0, scale = 0.0;
  for (int n = 0; n < steps; ++n) {
    const double t = n * dt;
    BOOST_TEST_REQUIRE(stepper.step(fused, problem.materials, t, dt));
    BOOST_TEST_REQUIRE(reference.step(unfused, problem.materials, t, dt));
    worst = std::max(worst, (fused.state - unfused.state).cwiseAbs().maxCoeff());
    if constexpr (Physics::n_internal > 0)
      worst = std::max(worst, (fused.internal - unfused.internal).cwiseAbs().maxCoeff());
    scale = std::max(scale, unfused.state.cwiseAbs().maxCoeff());
  }
  BOOST_TEST_REQUIRE(scale > 0.0);
  if constexpr (Physics::n_internal > 0)
    BOOST_TEST_REQUIRE(unfused.internal.cwiseAbs().maxCoeff() > 0.0);  // plastic flow happened
  return worst / scale;
}

void check_every_scene() {
  for (const std::string integrator : {"euler", "rk2"}) {
    BOOST_TEST_CONTEXT(integrator) {
      const std::vector<std::pair<std::string, double>> differences{
          {"1D", largest_difference<ElasticBar>(bar(integrator), 40)},
          {"1D periodic",
           largest_difference<ElasticBar>(test::periodic(bar(integrator), {true}), 40)},
          {"1D plastic", largest_difference<ElastoPlasticBar>(test::plastic(bar(integrator)), 40)},
          {"2D", largest_difference<PlaneStrain>(plate(integrator), 20)},
          {"2D periodic", largest_difference<PlaneStrain>(
                              test::periodic(test::filled(plate(integrator)), {true, true}), 20)},
          {"2D periodic along x",
           largest_difference<PlaneStrain>(test::periodic(plate(integrator), {true, false}), 20)},
          {"2D plastic",
           largest_difference<PlaneStrainPlastic>(test::plastic(plate(integrator)), 20)},
          {"2D CTU", largest_difference<PlaneStrain>(plate(integrator, "ctu"), 20)},
          {"2D CTU periodic",
           largest_difference<PlaneStrain>(
               test::periodic(test::filled(plate(integrator, "ctu")), {true, true}), 20)},
          {"2D CTU periodic along x",
           largest_difference<PlaneStrain>(test::periodic(plate(integrator, "ctu"), {true, false}),
                                           20)},
          {"2D CTU plastic",
           largest_difference<PlaneStrainPlastic>(test::plastic(plate(integrator, "ctu")), 20)},
          {"2D finite strain",
           largest_difference<FiniteStrainPlane<NeoHookean>>(test::finite(plate(integrator)), 20)},
          {"2D finite strain CTU", largest_difference<FiniteStrainPlane<NeoHookean>>(
                                       test::finite(plate(integrator, "ctu")), 20)}};
      for (const auto& [name, difference] : differences) {
        BOOST_TEST_MESSAGE(integrator << ", " << name << ": largest difference " << difference);
        BOOST_TEST(difference == 0.0, name);
      }
    }
  }
}

}  // namespace

BOOST_AUTO_TEST_CASE(fused_steps_equal_the_reference_stepper_to_the_bit) {
  check_every_scene();
}
