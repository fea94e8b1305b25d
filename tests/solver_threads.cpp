// The step runs on OpenMP threads on large grids: one and two threads give the same particle
// states bit for bit (1D and 2D, Euler and RK2, DCU and CTU, boundaries, periodic axes, void
// cells, two materials, moving particles, the automatic time step; and the MPM baseline, USL, USF
// and MUSL, its scatters to the grid included), and the threaded path is the one taken.
#define BOOST_TEST_MODULE solver_threads
#include <boost/test/unit_test.hpp>

#include "common/loaded_scenes.hpp"
#include "solver/mpm.hpp"
#include "solver/scene.hpp"
#include "solver/simulation.hpp"

#include <nlohmann/json.hpp>
#include <omp.h>

#include <cmath>
#include <string>
#include <tuple>

using namespace dgmpm;
using nlohmann::json;

namespace {

json bar(const std::string& integrator, bool move) {
  return test::loaded_bar(6000, 1e-3, integrator, move);  // 6000 cells: threaded
}

json plate(const std::string& flux, const std::string& integrator, bool move, int ppc = 1) {
  return test::loaded_plate(80, 60, 0.05, ppc, flux, integrator, move);  // 4800 cells: threaded
}

// The scene under the MPM baseline (the DGMPM flux removed).
json mpm(json doc, const std::string& variant) {
  doc.erase("flux");
  doc["method"] = "mpm-" + variant;
  return doc;
}

// Particle states and positions after `steps` steps on `threads` threads.
template <class Physics>
Eigen::MatrixXd run(const json& doc, int threads, int steps) {
  omp_set_num_threads(threads);
  Simulation<Physics> sim(scene::parse_scene(doc, "threads"));
  for (int k = 0; k < steps; ++k) sim.step(sim.stable_time_step());  // recomputed with "auto"
  const auto& p = sim.particles();
  Eigen::MatrixXd out(p.state.rows() + p.position.rows(), p.size());
  out << p.state, p.position;
  return out;
}

template <class Physics>
void same_on_one_and_two_threads(const json& doc, const std::string& what) {
  const Eigen::MatrixXd one = run<Physics>(doc, 1, 12), two = run<Physics>(doc, 2, 12);
  BOOST_TEST_REQUIRE(one.allFinite());
  BOOST_TEST(((one.array() != 0).count() > 0), what << ": something happens");
  BOOST_TEST(((one.array() == two.array()).all()),
             what << ": bit for bit, largest difference " << (one - two).cwiseAbs().maxCoeff());
}

}  // namespace

BOOST_AUTO_TEST_CASE(the_threaded_path_is_taken_on_these_grids) {
  const Simulation<ElasticBar> bar_sim(scene::parse_scene(bar("euler", false), "threads"));
  const Simulation<PlaneStrain> plate_sim(
      scene::parse_scene(plate("dcu", "euler", false), "threads"));
  BOOST_TEST(bar_sim.problem().grid.num_cells() >= DGOperator<ElasticBar>::kThreadedCells);
  BOOST_TEST(plate_sim.problem().grid.num_cells() >= DGOperator<PlaneStrain>::kThreadedCells);
  const Simulation<PlaneStrain> mpm_sim(
      scene::parse_scene(mpm(plate("dcu", "euler", false, 2), "usl"), "threads"));
  BOOST_TEST(bar_sim.num_particles() >= Mpm<ElasticBar>::kThreadedParticles);
  BOOST_TEST(mpm_sim.num_particles() >= Mpm<PlaneStrain>::kThreadedParticles);
  omp_set_num_threads(2);
  BOOST_TEST(omp_get_max_threads() == 2);  // the comparisons below do run two threads
}

BOOST_AUTO_TEST_CASE(one_dimension) {
  for (const char* integrator : {"euler", "rk2"})
    for (bool move : {false, true})
      same_on_one_and_two_threads<ElasticBar>(
          bar(integrator, move), std::string("1D ") + integrator + (move ? " moving" : ""));
  same_on_one_and_two_threads<ElasticBar>(test::periodic(bar("euler", false), {true}),
                                          "1D euler periodic");
  json automatic = bar("rk2", true);  // the time step from the layouts, on threads
  automatic["time"]["courant"] = "auto";
  same_on_one_and_two_threads<ElasticBar>(automatic, "1D rk2 moving, auto dt");
}

BOOST_AUTO_TEST_CASE(two_dimensions) {
  for (const char* flux : {"dcu", "ctu"})
    for (const char* integrator : {"euler", "rk2"})
      same_on_one_and_two_threads<PlaneStrain>(plate(flux, integrator, false),
                                               std::string("2D ") + flux + " " + integrator);
  same_on_one_and_two_threads<PlaneStrain>(plate("dcu", "rk2", true), "2D dcu rk2 moving");
  for (const char* flux : {"dcu", "ctu"}) {
    same_on_one_and_two_threads<PlaneStrain>(
        test::periodic(test::filled(plate(flux, "euler", false)), {true, true}),
        std::string("2D ") + flux + " periodic");
    same_on_one_and_two_threads<PlaneStrain>(
        test::periodic(plate(flux, "rk2", false), {true, false}),
        std::string("2D ") + flux + " rk2 periodic along x");
  }
  // Finite strain: the time step from the particles' speeds (on threads), CTU's transverse media
  // from the edge states.
  for (const char* flux : {"dcu", "ctu"}) {
    json doc = plate(flux, "euler", false);
    for (auto& [name, material] : doc["materials"].items()) material["model"] = "neo_hookean";
    doc["time"]["courant"] = "auto";
    same_on_one_and_two_threads<FiniteStrainPlane<NeoHookean>>(
        doc, std::string("2D finite strain ") + flux + " auto");
  }
}

BOOST_AUTO_TEST_CASE(mpm_baseline) {
  for (const char* variant : {"usl", "usf", "musl"}) {
    same_on_one_and_two_threads<ElasticBar>(mpm(bar("euler", true), variant),
                                            std::string("1D MPM moving ") + variant);
    same_on_one_and_two_threads<PlaneStrain>(mpm(plate("dcu", "euler", true, 2), variant),
                                             std::string("2D MPM moving ") + variant);
  }
  same_on_one_and_two_threads<PlaneStrain>(
      mpm(test::periodic(plate("dcu", "euler", false, 2), {true, false}), "usl"),
      "2D MPM periodic along x");
  // The scatters' colours on periodic last axes, the last block of cell layers beside the first
  // (both holding particles): 1D, 64 blocks; 2D, 61 rows, each its own block, the last one in a
  // colour of its own.
  json ring = test::periodic(test::loaded_bar(5999, 1e-3, "euler", true), {true});
  ring["bodies"][0]["box"]["min"] = {-0.1};
  ring["bodies"][1]["box"]["max"] = {-0.1 + 5999 * 1e-3};
  for (const char* variant : {"usl", "musl"})
    same_on_one_and_two_threads<ElasticBar>(mpm(ring, variant),
                                            std::string("1D MPM periodic, odd cells ") + variant);
  same_on_one_and_two_threads<PlaneStrain>(
      mpm(test::periodic(test::filled(test::loaded_plate(80, 61, 0.05, 2, "dcu", "euler", true)),
                         {false, true}),
          "usl"),
      "2D MPM periodic along y, odd rows");
}

// The energies the history records every step are summed on threads over fixed blocks of
// particles: the same bits on one and two threads, and the kinetic energy that of a serial sum
// over the particles here (to round-off: the blocks regroup the sum).
BOOST_AUTO_TEST_CASE(energy_sums) {
  const json doc = test::loaded_plate(140, 90, 0.03, 2, "dcu", "euler", true);  // 3 blocks
  const auto energy = [&](int threads) {
    omp_set_num_threads(threads);
    Simulation<PlaneStrain> sim(scene::parse_scene(doc, "threads"));
    for (int k = 0; k < 12; ++k) sim.step(sim.stable_time_step());
    const auto& p = sim.particles();
    double kinetic = 0;
    for (int i = 0; i < p.size(); ++i)
      kinetic += 0.5 * p.mass[i] *
                 (p.state(PlaneStrain::vx, i) * p.state(PlaneStrain::vx, i) +
                  p.state(PlaneStrain::vy, i) * p.state(PlaneStrain::vy, i));
    BOOST_TEST_REQUIRE(p.size() > 16384);
    return std::make_tuple(sim.energy_parts(), kinetic, p.size());
  };
  const auto [one, serial, n] = energy(1);
  const auto [two, serial_two, n_two] = energy(2);
  BOOST_TEST(serial > 0.0);
  BOOST_TEST(serial == serial_two);  // the same particle states
  BOOST_TEST(one.kinetic == two.kinetic);
  BOOST_TEST(one.elastic == two.elastic);
  BOOST_TEST(one.elastic > 0.0);
  // Positive terms: each order's relative error is below n eps.
  BOOST_TEST(std::abs(one.kinetic - serial) <= 2.0 * n * 1.2e-16 * serial);
}
