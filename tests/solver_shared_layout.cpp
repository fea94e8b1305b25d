// Cells whose particles sit as a reference cell's sit share that layout's shape values,
// gradients and pseudo-stiffness (Discretisation): computed once per build by the code that
// computes any other cell's. A step must give the same particle states and internal variables to
// the last bit with and without the sharing, on scenes that mix cells of the shared layout with
// others: boundaries, void cells, two materials, massless nodes and part-full cells (particles
// moved off the lattice), periodic grids, plastic flow, finite strain, DCU and CTU, Euler and
// RK2, fixed and moving particles. The sharing must also be found where it applies: every full
// cell of a regular lattice, and in the mixed scenes some cells but not all. Interior cells
// (shared, with shared face neighbours) take the interior path (DCU and CTU) without face look-ups
// or boundary branches: with sharing off no cell is interior, so the same comparison checks that
// path against the general one.
#define BOOST_TEST_MODULE solver_shared_layout
#include <boost/test/unit_test.hpp>

#include "common/disturb.hpp"
#include "common/loaded_scenes.hpp"
#include "solver/problem.hpp"
#include "solver/scene.hpp"
#include "solver/simulation.hpp"

#include <nlohmann/json.hpp>

#include <algorithm>
#include <map>
#include <string>

using namespace dgmpm;
using nlohmann::json;

namespace {

struct Counts {
  int shared = 0, interior = 0, occupied = 0;
};

// Steps the scene `steps` times with and without shared layouts and checks the particles agree
// to the last bit after every step; moving particles follow their velocities and the
// discretisations are rebuilt. Returns the cells sharing the layout at the first build.
template <class Physics>
Counts check_same(const json& doc, int steps, bool disturbed) {
  const scene::Scene scene = scene::parse_scene(doc, "shared");
  Problem<Physics> problem = make_problem<Physics>(scene);
  if (disturbed) test::disturb(problem.particles, problem.grid);
  StepperOptions on = stepper_options(scene), off = on;
  off.share_layouts = false;
  Stepper<Physics> sharing(problem.grid, problem.boundaries, on);
  Stepper<Physics> alone(problem.grid, problem.boundaries, off);
  ParticlesOf<Physics> a = problem.particles, b = problem.particles;
  sharing.rebuild(a, problem.materials);
  alone.rebuild(b, problem.materials);
  Counts counts;
  counts.shared = sharing.discretisation().shared_cells();
  for (int c = 0; c < sharing.discretisation().num_cells(); ++c) {
    counts.occupied += sharing.discretisation().occupied(c);
    counts.interior += sharing.discretisation().interior(c);
    BOOST_TEST_REQUIRE(!alone.discretisation().interior(c));
  }
  BOOST_TEST_REQUIRE(alone.discretisation().shared_cells() == 0);

  const double dt = 0.4 * problem.grid.cell_size.minCoeff() / problem.max_wave_speed();
  constexpr int dim = Physics::dim;
  for (int n = 0; n < steps; ++n) {
    const double t = n * dt;
    BOOST_TEST_REQUIRE(sharing.step(a, problem.materials, t, dt));
    BOOST_TEST_REQUIRE(alone.step(b, problem.materials, t, dt));
    BOOST_TEST_REQUIRE((a.state == b.state), "step " << n);
    if constexpr (Physics::n_internal > 0) BOOST_TEST_REQUIRE((a.internal == b.internal));
    if (scene.particles_move) {
      // The velocity is the state's last dim components (elastic and plastic physics).
      a.position += dt * a.state.template bottomRows<dim>();
      b.position += dt * b.state.template bottomRows<dim>();
      sharing.rebuild(a, problem.materials);
      alone.rebuild(b, problem.materials);
    }
  }
  BOOST_TEST_REQUIRE(a.state.cwiseAbs().maxCoeff() > 0.0);
  return counts;
}

json bar(const std::string& integrator, bool move = false) {
  return test::loaded_bar(70, 0.1, integrator, move);
}

json plate(const std::string& integrator, const std::string& flux, int ppc, bool move = false) {
  return test::loaded_plate(20, 14, 0.25, ppc, flux, integrator, move);
}

// Some cells share the layout, not all; some of those are interior (not always in disturbed
// scenes: at 2 x 2 particles per cell no shared cell is left with four shared neighbours), not all.
void mixed(const Counts& c, bool disturbed) {
  BOOST_TEST(c.shared > 0);
  BOOST_TEST(c.shared < c.occupied);
  if (!disturbed) BOOST_TEST(c.interior > 0);
  BOOST_TEST(c.interior < c.shared);
}

}  // namespace

BOOST_AUTO_TEST_CASE(bars_step_the_same_with_and_without_shared_layouts) {
  for (const std::string integrator : {"euler", "rk2"})
    for (const bool disturbed : {false, true}) {
      BOOST_TEST_CONTEXT(integrator << (disturbed ? ", disturbed" : "")) {
        mixed(check_same<ElasticBar>(bar(integrator), 40, disturbed), disturbed);
        mixed(check_same<ElasticBar>(test::periodic(bar(integrator), {true}), 40, disturbed),
              disturbed);
        mixed(check_same<ElastoPlasticBar>(test::plastic(bar(integrator)), 40, disturbed),
              disturbed);
        check_same<ElasticBar>(bar(integrator, true), 40, disturbed);
      }
    }
}

BOOST_AUTO_TEST_CASE(plates_step_the_same_with_and_without_shared_layouts) {
  for (const std::string integrator : {"euler", "rk2"})
    for (const std::string flux : {"dcu", "ctu"})
      for (const int ppc : {1, 2})
        for (const bool disturbed : {false, true}) {
          BOOST_TEST_CONTEXT(integrator << ", " << flux << ", " << ppc << " ppc"
                                        << (disturbed ? ", disturbed" : "")) {
            const json doc = plate(integrator, flux, ppc);
            mixed(check_same<PlaneStrain>(doc, 15, disturbed), disturbed);
            mixed(check_same<PlaneStrain>(test::periodic(test::filled(doc), {true, true}), 15,
                                          disturbed),
                  disturbed);
            mixed(check_same<PlaneStrainPlastic>(test::plastic(doc), 15, disturbed), disturbed);
            check_same<PlaneStrain>(
                test::periodic(test::filled(plate(integrator, flux, ppc, true)), {true, true}), 15,
                disturbed);
          }
        }
  for (const std::string integrator : {"euler", "rk2"})
    for (const std::string flux : {"dcu", "ctu"})
      BOOST_TEST_CONTEXT("finite strain, " << integrator << ", " << flux) {
        mixed(check_same<FiniteStrainPlane<NeoHookean>>(test::finite(plate(integrator, flux, 1)),
                                                        15, false),
              false);
      }
}

// A periodic lattice: every cell holds the reference cell's particles.
BOOST_AUTO_TEST_CASE(every_cell_of_a_regular_lattice_shares_its_layout) {
  for (const int ppc : {1, 2}) {
    json doc = test::periodic(test::filled(plate("euler", "dcu", ppc)), {true, true});
    doc["bodies"] = json::array({doc["bodies"][0]});
    doc["bodies"][0]["box"]["max"][0] = 20 * 0.25;
    const Counts c = check_same<PlaneStrain>(doc, 5, false);
    BOOST_TEST(c.occupied == 20 * 14);
    BOOST_TEST(c.shared == c.occupied);
    // Not the cells of the first and last rows and columns: their neighbours across the periodic
    // sides are not at c +- stride.
    BOOST_TEST(c.interior == (20 - 2) * (14 - 2));
  }
}

// A lattice placed at (i + 1/2) h, h = 1 / 4000: x / h - i is 1/2 in most cells but a few last
// bits off it in others, the middle cell among them. The shared layout is the most common one:
// exactly the cells whose located coordinate is the most common value share it.
BOOST_AUTO_TEST_CASE(the_shared_layout_is_the_most_common_one) {
  const int cells = 4000;
  const json doc = {
      {"dimension", 1},
      {"grid",
       {{"origin", {0.0}}, {"cell_size", {1.0 / cells}}, {"cells", {cells}}, {"periodic", true}}},
      {"materials", {{"steel", {{"young", 2e11}, {"density", 7800}}}}},
      {"bodies",
       {{{"material", "steel"},
         {"box", {{"min", {0.0}}, {"max", {1.0}}}},
         {"particles_per_cell", 1},
         {"velocity", {1.0}}}}},
      {"time", {{"end", 1e-6}, {"courant", 0.5}}}};
  const scene::Scene scene = scene::parse_scene(doc, "lattice");
  const Problem<ElasticBar> problem = make_problem<ElasticBar>(scene);
  std::map<double, int> count;
  Eigen::Matrix<double, 1, 1> xi = Eigen::Matrix<double, 1, 1>::Zero();
  double middle = -1.0;
  for (int p = 0; p < problem.particles.size(); ++p) {
    const int c = problem.grid.locate(problem.particles.position.col(p), xi);
    ++count[xi[0]];
    if (c == cells / 2) middle = xi[0];
  }
  const auto common = std::max_element(count.begin(), count.end(),
                                       [](auto& a, auto& b) { return a.second < b.second; });
  BOOST_TEST_REQUIRE(common->first == 0.5);
  BOOST_TEST_REQUIRE(middle != 0.5);  // a reference taken from the middle shares with few
  const Counts c = check_same<ElasticBar>(doc, 3, false);
  BOOST_TEST(c.occupied == cells);
  BOOST_TEST(c.shared == common->second);
  BOOST_TEST(c.shared > 0.95 * cells);
}
