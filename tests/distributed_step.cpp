// Run under mpirun (2 and 4 ranks): a scene distributed over the ranks steps to the same particle
// states and positions, bit for bit, as the serial run of the same scene, which every rank also
// runs as the reference: 1D and 2D, DCU and CTU, Euler and RK2, fixed and moving particles
// (migrating between ranks), the automatic time step, traction segments and rollers across rank
// boundaries, periodic axes split over ranks. And `mpirun dgmpm run` writes the serial run's CSV
// files byte for byte.
#define BOOST_TEST_MODULE distributed_step
#include <boost/test/unit_test.hpp>

#include "common/loaded_scenes.hpp"
#include "common/mpi_session.hpp"
#include "mpi_communicator.hpp"
#include "solver/scene.hpp"
#include "solver/simulation.hpp"

#include <mpi.h>
#include <nlohmann/json.hpp>

#include <set>
#include <string>
#include <vector>

using namespace dgmpm;
using nlohmann::json;

namespace {

int world_size() {
  int n = 0;
  MPI_Comm_size(MPI_COMM_WORLD, &n);
  return n;
}

long sum_over_ranks(long v) {
  MPI_Allreduce(MPI_IN_PLACE, &v, 1, MPI_LONG, MPI_SUM, MPI_COMM_WORLD);
  return v;
}

struct Outcome {
  long compared = 0, differing = 0, migrated = 0;
  std::size_t warnings = 0;
  double largest = 0;
};

// Steps the scene `steps` times serially and distributed; compares every rank's owned particles
// with the serial run's (through their index in the serial arrays). Migrated: particles owned at
// the end by another rank than at the start.
template <class Physics>
Outcome compare(const json& doc, int steps) {
  const scene::Scene scene = scene::parse_scene(doc, "distributed");
  Simulation<Physics> serial(scene);
  distributed::MpiCommunicator world(MPI_COMM_WORLD);
  Simulation<Physics> split(scene, &world);
  BOOST_TEST_REQUIRE(split.halo() != nullptr);
  std::set<int> owned_before;
  for (int i = 0; i < split.owned_particles(); ++i) owned_before.insert(split.particles().id[i]);
  for (int k = 0; k < steps; ++k) {
    BOOST_TEST_REQUIRE(serial.stable_time_step() == split.stable_time_step());
    const double dt = serial.stable_time_step();
    serial.step(dt);
    split.step(dt);
  }
  Outcome o;
  const auto& s = serial.particles();
  const auto& d = split.particles();
  for (int i = 0; i < split.owned_particles(); ++i) {
    const long g = split.halo()->global_index(i);
    const bool same = (d.state.col(i).array() == s.state.col(g).array()).all() &&
                      (d.position.col(i).array() == s.position.col(g).array()).all() &&
                      d.id[i] == s.id[g];
    o.differing += !same;
    o.largest = std::max(o.largest, (d.state.col(i) - s.state.col(g)).cwiseAbs().maxCoeff());
    o.migrated += !owned_before.count(d.id[i]);
  }
  // The same warnings on every rank as in the serial run (over-full cells found by any rank).
  BOOST_TEST(split.warnings() == serial.warnings());

  o.warnings = serial.warnings().size();
  o.compared = sum_over_ranks(split.owned_particles());
  o.differing = sum_over_ranks(o.differing);
  o.migrated = sum_over_ranks(o.migrated);
  BOOST_TEST(o.compared == serial.particles().size());  // each particle owned once
  BOOST_TEST_REQUIRE(s.state.allFinite());
  BOOST_TEST(((s.state.array() != 0).count() > 0));  // something happens
  return o;
}

template <class Physics>
void same_as_serial(const json& doc, const std::string& what, int steps = 12) {
  const Outcome o = compare<Physics>(doc, steps);
  BOOST_TEST(o.differing == 0, what << ": " << o.differing << " of " << o.compared
                                    << " particles differ (largest state difference on this rank "
                                    << o.largest << ")");
}

json bar(const std::string& integrator, bool move) {
  return test::loaded_bar(60, 0.1, integrator, move);
}

// The plate with its traction segment reaching across the ranks' split at y = 2.
json plate(const std::string& flux, const std::string& integrator, bool move, int ppc = 2) {
  json doc = test::loaded_plate(24, 16, 0.25, ppc, flux, integrator, move);
  doc["boundaries"]["xmin"][0]["range"] = {0.0, 3.0};
  return doc;
}

// Bodies fast enough to cross cells (and ranks) within the steps: soft bodies at a fifth of their
// wave speed.
json fast(json doc) {
  doc["particles_move"] = true;
  for (auto& body : doc["bodies"]) {
    body["material"] = "soft";
    if (body.contains("velocity"))
      for (auto& v : body["velocity"]) v = v.get<double>() > 0 ? 300.0 : -300.0;
  }
  return doc;
}

}  // namespace

BOOST_AUTO_TEST_CASE(one_dimension) {
  for (const char* integrator : {"euler", "rk2"})
    for (bool move : {false, true})
      same_as_serial<ElasticBar>(bar(integrator, move),
                                 std::string("1D ") + integrator + (move ? " moving" : ""));
  json automatic = bar("rk2", true);
  automatic["time"]["courant"] = "auto";
  same_as_serial<ElasticBar>(automatic, "1D rk2 moving, automatic time step");
  same_as_serial<ElasticBar>(test::periodic(bar("euler", false), {true}), "1D periodic euler");
  same_as_serial<ElasticBar>(test::periodic(bar("rk2", true), {true}), "1D periodic rk2 moving");
}

BOOST_AUTO_TEST_CASE(two_dimensions) {
  for (const char* flux : {"dcu", "ctu"})
    for (const char* integrator : {"euler", "rk2"})
      for (bool move : {false, true})
        same_as_serial<PlaneStrain>(plate(flux, integrator, move), std::string("2D ") + flux + " " +
                                                                       integrator +
                                                                       (move ? " moving" : ""));
  // One particle per cell: a 2D analysis per material, not per layout (seconds each).
  json automatic = plate("dcu", "euler", true, 1);
  automatic["time"]["courant"] = "auto";
  same_as_serial<PlaneStrain>(automatic, "2D dcu euler moving, automatic time step");
}

BOOST_AUTO_TEST_CASE(periodic_axes_split_over_ranks) {
  for (const char* flux : {"dcu", "ctu"}) {
    same_as_serial<PlaneStrain>(
        test::periodic(test::filled(plate(flux, "euler", false)), {true, true}),
        std::string("2D torus ") + flux);
    same_as_serial<PlaneStrain>(
        test::periodic(test::filled(plate(flux, "rk2", true)), {true, false}),
        std::string("2D tube rk2 moving ") + flux);
  }
}

BOOST_AUTO_TEST_CASE(particles_migrate_between_ranks) {
  json ring = fast(test::periodic(bar("rk2", true), {true}));
  ring["time"]["courant"] = "auto";
  ring["formulation"] =
      "paper";  // warns about over-full cells (the consistent form has no cause to)
  const Outcome bar_run = compare<ElasticBar>(ring, 30);
  BOOST_TEST(bar_run.differing == 0);
  BOOST_TEST(bar_run.migrated > 0, "1D: " << bar_run.migrated << " particles changed rank");
  BOOST_TEST(bar_run.warnings > 0);  // the impact piles particles up: an over-full cell
  const Outcome plate_run = compare<PlaneStrain>(
      fast(test::periodic(test::filled(plate("dcu", "euler", true)), {true, true})), 60);
  BOOST_TEST(plate_run.differing == 0);
  BOOST_TEST(plate_run.migrated > 0, "2D: " << plate_run.migrated << " particles changed rank");
}

// A moving step writes the new local set into the one the step before replaced (Halo::migrate
// swaps two sets): where the count is that of two steps before, the arrays are the same memory,
// nothing allocated.
BOOST_AUTO_TEST_CASE(a_migration_keeping_the_count_reuses_the_arrays) {
  const scene::Scene scene = scene::parse_scene(bar("euler", true), "distributed");
  distributed::MpiCommunicator world(MPI_COMM_WORLD);
  Simulation<ElasticBar> split(scene, &world);
  const double dt = split.stable_time_step();
  split.step(dt);  // the first migration allocates the second set
  std::vector<const double*> state, position;
  std::vector<int> count;
  for (int k = 0; k < 12; ++k) {
    state.push_back(split.particles().state.data());
    position.push_back(split.particles().position.data());
    count.push_back(split.particles().size());
    split.step(dt);
  }
  int reused = 0;
  for (std::size_t k = 2; k < count.size(); ++k) {
    BOOST_TEST(state[k] != state[k - 1]);  // two sets, alternating
    if (count[k] != count[k - 2]) continue;
    BOOST_TEST(state[k] == state[k - 2], "step " << k);
    BOOST_TEST(position[k] == position[k - 2], "step " << k);
    ++reused;
  }
  BOOST_TEST(reused > 0);
}

BOOST_AUTO_TEST_CASE(a_grid_too_small_for_the_ranks_is_refused_on_every_rank) {
  json doc = test::periodic(bar("rk2", false), {true});
  doc["grid"]["cells"] = {world_size() + 1};  // blocks of one or two cells, two ghost layers
  doc["grid"]["cell_size"] = {6.0 / (world_size() + 1)};
  distributed::MpiCommunicator world(MPI_COMM_WORLD);
  BOOST_CHECK_EXCEPTION(Simulation<ElasticBar>(scene::parse_scene(doc, "small"), &world),
                        scene::SceneError, [](const scene::SceneError& e) {
                          return std::string(e.what()).find("cannot be split over") !=
                                 std::string::npos;
                        });
}
