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

// A finite-strain step is not a linear map: no whole-scene operator, refused naming the model.
BOOST_AUTO_TEST_CASE(finite_strain_scenes_are_refused) {
  json doc = bar(8, {{"particles_per_cell", 1}}, true, "euler");
  for (auto& [name, m] : doc["materials"].items()) m["model"] = "neo_hookean";
  for (auto& b : doc["bodies"]) b.erase("stress");
  try {
    analyse_scene_spectrum(scene::parse_scene(doc));
    BOOST_ERROR("no SceneError");
  } catch (const scene::SceneError& e) {
    BOOST_TEST(std::string(e.what()).find("model: value \"neo_hookean\" has no linear scene "
                                          "operator") != std::string::npos,
               e.what());
  }
}

// A small 2D plate with free, traction and roller edges, one particle per cell at the centre:
// the whole scene's limit agrees with the layout analysis of its cells (C* = 1 for DCU with RK2
// and CTU with Euler), to the percent that the boundaries may add.
BOOST_AUTO_TEST_CASE(small_plate_agrees_with_the_layout_analysis) {
  for (const auto& [flux, integrator] : {std::pair{"dcu", "rk2"}, std::pair{"ctu", "euler"}}) {
    BOOST_TEST_CONTEXT(flux << ", " << integrator) {
      const json doc = {
          {"dimension", 2},
          {"flux", flux},
          {"grid", {{"origin", {0.0, 0.0}}, {"cell_size", {0.1, 0.1}}, {"cells", {6, 5}}}},
          {"materials", {{"steel", {{"young", 2e11}, {"poisson", 0.3}, {"density", 7800}}}}},
          {"bodies",
           {{{"material", "steel"},
             {"box", {{"min", {0.0, 0.0}}, {"max", {0.6, 0.5}}}},
             {"particles_per_cell", {1, 1}}}}},
          {"boundaries",
           {{"xmin", {{{"type", "traction"}, {"value", {-1e8, 0.0}}, {"range", {0.0, 0.25}}}}},
            {"ymin", {{"type", "roller"}}}}},
          {"time", {{"end", 1e-4}, {"integrator", integrator}, {"courant", 1.0}}}};
      const auto r = analyse_scene_spectrum(scene::parse_scene(doc));
      stability::AnalysisSetting s;
      s.dim = 2;
      s.flux = std::string(flux) == "ctu" ? FluxScheme::ctu : FluxScheme::dcu;
      s.time = std::string(integrator) == "rk2" ? TimeScheme::rk2 : TimeScheme::euler;
      const double layout =
          stability::admissible_courant({{0.5, 0.5}, {}, 2}, s, stability::Criterion::l2).courant;
      BOOST_TEST_MESSAGE(flux << " " << integrator << ": scene " << r.courant << ", layout "
                              << layout);
      BOOST_TEST(layout == 1.0, boost::test_tools::tolerance(1e-6));
      BOOST_TEST(r.courant >= 0.99 * layout);
      BOOST_TEST(r.courant <= 1.05 * layout);
      BOOST_TEST(r.unknowns == 150);
    }
  }
}
