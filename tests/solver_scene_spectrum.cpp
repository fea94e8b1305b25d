// Whole-scene stability through ARPACK, each product one step of the solver's own operators.
#define BOOST_TEST_MODULE scene_spectrum
#include <boost/test/unit_test.hpp>

#include "solver/scene_spectrum.hpp"

#include <stability/admissible_courant.hpp>

#include <nlohmann/json.hpp>

#include <string>

using namespace dgmpm;
using nlohmann::json;

namespace {
json bar(int cells, json layout, bool periodic, const std::string& integrator) {
  json body = {{"material", "steel"},
               {"box", {{"min", {0.0}}, {"max", {cells * 0.04}}}},
               {"velocity", {1.0}}};
  body.update(layout);
  return {{"dimension", 1},
          {"grid",
           {{"origin", {0.0}}, {"cell_size", {0.04}}, {"cells", {cells}}, {"periodic", periodic}}},
          {"materials", {{"steel", {{"young", 2e11}, {"density", 7800}}}}},
          {"bodies", {body}},
          {"time", {{"end", 1e-3}, {"integrator", integrator}, {"courant", 0.5}}}};
}
}  // namespace

BOOST_AUTO_TEST_CASE(one_particle_per_cell_admits_courant_one) {
  for (bool periodic : {true, false})
    for (const char* integrator : {"euler", "rk2"}) {
      BOOST_TEST_CONTEXT((periodic ? "periodic " : "free ends ") << integrator) {
        const auto r = analyse_scene_spectrum(
            scene::parse_scene(bar(24, {{"particles_per_cell", 1}}, periodic, integrator)));
        BOOST_TEST(r.courant == 1.0, boost::test_tools::tolerance(1e-5));
        BOOST_TEST(r.unknowns == 48);
        BOOST_TEST(r.radius_at_scene_courant <= 1.0 + 1e-9);
        // Euler with one particle per cell: the eigenvalues of lib's operator, computed once
        // (checked against the scene's own step); RK2: ARPACK per Courant number. Both give 1.
        const bool euler = std::string(integrator) == "euler";
        BOOST_TEST((r.method.find(euler ? "eigenvalues" : "ARPACK") != std::string::npos),
                   r.method);
      }
    }
}

BOOST_AUTO_TEST_CASE(periodic_scene_limit_is_at_least_the_von_neumann_limit) {
  // The grid's wavenumbers are a subset of (0, pi]: its limit cannot be below the continuous one.
  const auto r = analyse_scene_spectrum(
      scene::parse_scene(bar(32, {{"particles_per_cell", 2}}, true, "euler")));
  const double vn =
      stability::admissible_courant(stability::regular_layout(2), stability::TimeScheme::euler,
                                    stability::Criterion::l2)
          .courant;
  BOOST_TEST(vn == 0.686, boost::test_tools::tolerance(2e-3));
  BOOST_TEST(r.courant >= vn - 1e-5);
  BOOST_TEST(r.courant < 1.0);
  BOOST_TEST(r.boundaries == "periodic");
}

BOOST_AUTO_TEST_CASE(mpm_scenes_are_refused) {
  json doc = bar(8, {{"particles_per_cell", 1}}, true, "euler");
  doc["method"] = "mpm-usl";
  BOOST_CHECK_THROW(analyse_scene_spectrum(scene::parse_scene(doc)), scene::SceneError);
}
