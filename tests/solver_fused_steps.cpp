// DCU steps are fused: one pass over the cells per stage projects each cell (a layer of cells
// ahead), computes its whole residual and update (and, for Euler and RK2's last stage, its
// particles). The unfused definition is the composition of the operator's four stages, project
// -> residual (face by face) -> update -> interpolate, written out here for Euler and Heun's RK2:
// both must give the same particle states, on 1D and 2D scenes with boundaries (traction, free,
// roller), periodic axes, void cells, massless nodes, over-full and empty cells inside a body,
// and two materials; and CTU's steps (which compose the stages inside the operator) too.
#define BOOST_TEST_MODULE solver_fused_steps
#include <boost/test/unit_test.hpp>

#include "common/loaded_scenes.hpp"
#include "solver/problem.hpp"
#include "solver/scene.hpp"
#include "solver/simulation.hpp"

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

// Moves particles so that some nodes are massless (a particle on its cell's lower node along
// every axis), some cells inside the body over-full and others empty.
template <int Dim, int NComp>
void disturb(Particles<Dim, NComp>& p, const Grid<Dim>& grid) {
  for (int k = 0; k < p.size(); k += 7) {
    Eigen::Matrix<double, Dim, 1> xi;
    const int c = grid.locate(p.position.col(k), xi);
    const auto index = grid.unflatten(c);
    for (int a = 0; a < Dim; ++a) p.position(a, k) = grid.origin[a] + index[a] * grid.cell_size[a];
  }
  for (int k = 3; k < p.size(); k += 11) p.position(0, k) += grid.cell_size[0];
}

template <class Physics>
double largest_difference(const json& doc, int steps) {
  const scene::Scene scene = scene::parse_scene(doc, "fused");
  Problem<Physics> problem = make_problem<Physics>(scene);
  disturb(problem.particles, problem.grid);
  const StepperOptions options = stepper_options(scene);
  Stepper<Physics> stepper(problem.grid, problem.boundaries, options);
  stepper.rebuild(problem.particles, problem.materials);
  const auto& op = stepper.op();
  const auto& disc = stepper.discretisation();
  BOOST_TEST_REQUIRE(disc.has_massless_nodes());
  int empty = 0;
  for (int c = 0; c < disc.num_cells(); ++c) empty += !disc.occupied(c);
  BOOST_TEST_REQUIRE(empty > 0);

  const Eigen::VectorXd& mass = problem.particles.mass;
  const double dt = 0.4 * problem.grid.cell_size.minCoeff() / problem.max_wave_speed();
  using Op = DGOperator<Physics>;
  typename Op::ParticleField fused = problem.particles.state, unfused = fused;
  typename Op::NodalField q0, q1, r;
  double worst = 0.0, scale = 0.0;
  for (int n = 0; n < steps; ++n) {
    const double t = n * dt;
    stepper.step(fused, mass, t, dt);
    // The unfused definition.
    op.project(unfused, mass, q0);
    op.residual(q0, t, dt, r);
    if (options.time == TimeScheme::euler) {
      op.update(q0, r, dt);
      op.interpolate(q0, unfused);
    } else {
      q1 = q0;
      op.update(q1, r, dt);
      op.residual(q1, t + dt, dt, r);
      op.update(q1, r, dt);
      q0 = 0.5 * (q0 + q1);
      op.interpolate(q0, unfused);
    }
    worst = std::max(worst, (fused - unfused).cwiseAbs().maxCoeff());
    scale = std::max(scale, unfused.cwiseAbs().maxCoeff());
  }
  BOOST_TEST_REQUIRE(fused.allFinite());
  BOOST_TEST_REQUIRE(scale > 0.0);
  return worst / scale;
}

}  // namespace

BOOST_AUTO_TEST_CASE(fused_steps_equal_the_composition_of_the_stages) {
  for (const std::string integrator : {"euler", "rk2"}) {
    BOOST_TEST_CONTEXT(integrator) {
      const double bar_difference = largest_difference<ElasticBar>(bar(integrator), 40);
      const double plate_difference = largest_difference<PlaneStrain>(plate(integrator), 20);
      BOOST_TEST_MESSAGE(integrator << ": largest relative difference, 1D " << bar_difference
                                    << ", 2D " << plate_difference);
      BOOST_TEST(bar_difference <= 1e-14);
      BOOST_TEST(plate_difference <= 1e-14);
      const double ring =
          largest_difference<ElasticBar>(test::periodic(bar(integrator), {true}), 40);
      const double torus =
          largest_difference<PlaneStrain>(test::periodic(plate(integrator), {true, true}), 20);
      const double tube =
          largest_difference<PlaneStrain>(test::periodic(plate(integrator), {true, false}), 20);
      BOOST_TEST_MESSAGE(integrator << ": periodic 1D " << ring << ", 2D " << torus
                                    << ", 2D periodic along x " << tube);
      BOOST_TEST(ring <= 1e-14);
      BOOST_TEST(torus <= 1e-14);
      BOOST_TEST(tube <= 1e-14);
      const double ctu = largest_difference<PlaneStrain>(plate(integrator, "ctu"), 20);
      BOOST_TEST_MESSAGE(integrator << ": CTU " << ctu);
      BOOST_TEST(ctu <= 1e-14);
    }
  }
}
