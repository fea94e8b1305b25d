// Two independent codes, one scheme: in 1D with one particle per cell at the cell centres and
// fixed particles, DGMPM with forward Euler and MPM USL with the PIC velocity update produce the
// same particle states to round-off inside a body and at a traction-loaded end (found in the
// report's tables, where their errors agree to 10 digits on every grid), as long as no wave has
// reached a free end (there the two treat the boundary differently: DGMPM solves a Riemann
// problem against a ghost state, MPM leaves the end nodes free; the states then differ by about
// 1e-3 relative). A change to either code's projection, fluxes, traction or update breaks the
// agreement.
#define BOOST_TEST_MODULE solver_dgmpm_mpm_agreement
#include <boost/test/unit_test.hpp>

#include "solver/scene.hpp"
#include "solver/simulation.hpp"

#include <nlohmann/json.hpp>

#include <cmath>

using namespace dgmpm;
using nlohmann::json;

namespace {

json body(double lo, double hi, double v) {
  return {{"material", "steel"},
          {"box", {{"min", {lo}}, {"max", {hi}}}},
          {"velocity", {v}},
          {"particles_per_cell", 1}};
}

json bar(const std::string& method, bool traction) {
  const double v = traction ? 0.0 : 20.0;
  json doc = {{"dimension", 1},
              {"method", method},
              {"grid", {{"origin", {0.0}}, {"cell_size", {0.05}}, {"cells", {40}}}},
              {"materials", {{"steel", {{"young", 2e11}, {"density", 7800}}}}},
              {"bodies", json::array({body(0.0, 1.0, v), body(1.0, 2.0, -v)})},
              // Waves travel 0.8 m: from the impact at x = 1 or the loaded end at x = 2, none
              // reaches a free end.
              {"time", {{"end", 0.8 / std::sqrt(2e11 / 7800)}, {"courant", 0.5}}}};
  if (traction)
    doc["boundaries"] = {
        {"xmin", {{"type", "free"}}},
        {"xmax",
         {{"type", "traction"}, {"value", {{0.0, 0.0}, {5e-5, -1e8}, {1e-4, 0.0}, {1.0, 0.0}}}}}};
  if (method == "mpm-usl") doc["update"] = "pic";
  return doc;
}

Eigen::MatrixXd final_state(const json& doc) {
  BarSimulation sim(scene::parse_scene(doc, "agreement"));
  sim.advance_to(sim.scene().time.end);
  return sim.physical_state();
}

}  // namespace

BOOST_AUTO_TEST_CASE(dgmpm_euler_one_particle_equals_mpm_usl_pic) {
  for (bool traction : {false, true}) {
    const Eigen::MatrixXd dg = final_state(bar("dgmpm", traction));
    const Eigen::MatrixXd mpm = final_state(bar("mpm-usl", traction));
    BOOST_TEST_REQUIRE(dg.cols() == mpm.cols());
    // Something happened (waves crossed the bars) and the two agree to round-off.
    const double scale_stress = dg.row(0).cwiseAbs().maxCoeff();
    const double scale_velocity = dg.row(1).cwiseAbs().maxCoeff();
    BOOST_TEST(scale_stress > 1e6);
    BOOST_TEST((dg.row(0) - mpm.row(0)).cwiseAbs().maxCoeff() <= 1e-10 * scale_stress,
               (traction ? "traction" : "impact")
                   << ": stress, largest difference "
                   << (dg.row(0) - mpm.row(0)).cwiseAbs().maxCoeff() << " of " << scale_stress);
    BOOST_TEST((dg.row(1) - mpm.row(1)).cwiseAbs().maxCoeff() <= 1e-10 * scale_velocity,
               (traction ? "traction" : "impact") << ": velocity");
  }
}
