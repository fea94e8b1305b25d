// 2D plane-strain scenes through the solver: two blocks meeting (P and S waves) against the 1D
// exact solution, the roller as a symmetry plane, energy against the work of the load, the exact
// force of a partly loaded edge, the MPM baseline on the same scenes, and refused 2D inputs.
#define BOOST_TEST_MODULE solver_plane_strain
#include <boost/test/unit_test.hpp>

#include <solver/scene.hpp>
#include <solver/simulation.hpp>

#include <nlohmann/json.hpp>

#include <cmath>
#include <fstream>
#include <string>

using namespace dgmpm;
using json = nlohmann::json;
using PS = PlaneStrain;

namespace {

const double young = 2e11, nu = 0.3, rho = 7800;
const PS::Material steel(young, nu, rho);

// Two blocks of n cells each along `axis`, `width` cells across (periodic across), meeting at
// the middle with velocities +-v (along `axis` for a P wave, across it for an S wave).
json blocks(int axis, bool shear, int n, int width, const std::string& flux,
            const std::string& integrator, double courant, double end) {
  const double h = 0.1;
  json cells = axis == 0 ? json::array({2 * n, width}) : json::array({width, 2 * n});
  json periodic = axis == 0 ? json::array({false, true}) : json::array({true, false});
  const double length = n * h, across = width * h;
  const auto box = [&](double from, double to) {
    return axis == 0 ? json{{"min", {from, 0.0}}, {"max", {to, across}}}
                     : json{{"min", {0.0, from}}, {"max", {across, to}}};
  };
  const auto velocity = [&](double v) {
    const int k = shear ? 1 - axis : axis;
    json u = {0.0, 0.0};
    u[k] = v;
    return u;
  };
  return {
      {"dimension", 2},
      {"flux", flux},
      {"grid",
       {{"origin", {0.0, 0.0}}, {"cell_size", {h, h}}, {"cells", cells}, {"periodic", periodic}}},
      {"materials", {{"steel", {{"young", young}, {"poisson", nu}, {"density", rho}}}}},
      {"bodies",
       {{{"material", "steel"},
         {"box", box(0.0, length)},
         {"particles_per_cell", {1, 1}},
         {"velocity", velocity(10.0)}},
        {{"material", "steel"},
         {"box", box(length, 2 * length)},
         {"particles_per_cell", {1, 1}},
         {"velocity", velocity(-10.0)}}}},
      {"time", {{"end", end}, {"integrator", integrator}, {"courant", courant}}}};
}

// The 1D exact solution of two bars of length L = n h meeting at x = L with +-v0, free ends,
// wave speed c, impedance z, at t <= 3 L / (2 c) (one reflection at the free ends): the stress
// and the velocity (along the wave's polarisation) at x.
std::pair<double, double> two_bars(double x, double t, double length, double c, double z,
                                   double v0) {
  const double front = c * t;               // distance travelled from the contact
  const double reflected = c * t - length;  // distance travelled back from the free ends
  const double d = std::abs(x - length);
  if (reflected > 0) {  // release waves from the ends, at distance `reflected` from them
    if (d < length - reflected) return {-z * v0, 0.0};
    return {0.0, x < length ? -v0 : v0};
  }
  if (d < front) return {-z * v0, 0.0};
  return {0.0, x < length ? v0 : -v0};
}

// Checks the fields of a blocks run against two_bars: the P (or S) pair exact, the other
// family at zero, sigma_tt = lambda / (lambda + 2 mu) sigma_nn for the P wave.
void check_blocks(int axis, bool shear, const std::string& flux, const std::string& integrator,
                  int steps) {
  const int n = 20;
  const double h = 0.1, c = shear ? steel.s_speed() : steel.p_speed();
  const double z = shear ? steel.s_impedance() : steel.p_impedance(), v0 = 10.0;
  const double courant = steel.p_speed() / c;  // c dt / h = 1 for the wave's family
  const double end = steps * h / c;
  PlaneStrainSimulation sim(
      scene::parse_scene(blocks(axis, shear, n, 3, flux, integrator, courant, end)));
  sim.advance_to(end);
  BOOST_REQUIRE(sim.steps() == steps);
  const auto s = sim.physical_state();
  const auto& x = sim.particles().position;
  const int nn = axis == 0 ? PS::sxx : PS::syy, tt = axis == 0 ? PS::syy : PS::sxx;
  const int vn = PS::vx + axis, vt = PS::vx + 1 - axis;
  double err = 0;
  for (int p = 0; p < sim.particles().size(); ++p) {
    const auto [se, ve] = two_bars(x(axis, p), end, n * h, c, z, v0);
    if (shear) {
      err = std::max({err, std::abs(s(PS::sxy, p) - se) / (z * v0), std::abs(s(vt, p) - ve) / v0,
                      std::abs(s(nn, p)) / (z * v0), std::abs(s(tt, p)) / (z * v0),
                      std::abs(s(vn, p)) / v0});
    } else {
      err = std::max({err, std::abs(s(nn, p) - se) / (z * v0), std::abs(s(vn, p) - ve) / v0,
                      std::abs(s(tt, p) - steel.lambda() / steel.p_modulus() * s(nn, p)) / (z * v0),
                      std::abs(s(PS::sxy, p)) / (z * v0), std::abs(s(vt, p)) / v0});
    }
  }
  BOOST_TEST(err < 1e-10, flux << ", " << integrator << ": max relative error " << err);
}

Eigen::VectorXd momentum(const PlaneStrainSimulation& sim, int axis) {
  const auto& p = sim.particles();
  return (p.mass.array() * p.state.row(PS::vx + axis).transpose().array()).matrix();
}

json plate(const std::string& flux, const std::string& integrator, double courant, double end,
           bool roller_bottom, double height = 3.0, double load_from = 0.0, double load_to = 1.0) {
  const int rows = static_cast<int>(std::lround(height / 0.12));
  json doc = {
      {"dimension", 2},
      {"flux", flux},
      {"grid", {{"origin", {0.0, 0.0}}, {"cell_size", {4.0 / 33, 0.12}}, {"cells", {33, rows}}}},
      {"materials", {{"steel", {{"young", young}, {"poisson", nu}, {"density", rho}}}}},
      {"bodies",
       {{{"material", "steel"},
         {"box", {{"min", {0.0, 0.0}}, {"max", {4.0, height}}}},
         {"particles_per_cell", {1, 1}}}}},
      {"boundaries",
       {{"xmin",
         {{{"type", "traction"}, {"value", {-2e8, 0.0}}, {"range", {load_from, load_to}}}}}}},
      {"time", {{"end", end}, {"integrator", integrator}, {"courant", courant}}}};
  if (roller_bottom) doc["boundaries"]["ymin"] = {{"type", "roller"}};
  return doc;
}

}  // namespace

// Two blocks meeting with opposite x velocities (and the same along y), one particle per cell,
// c_p dt / dx = 1: the 1D exact solution with the P-wave modulus. DCU with RK2 and CTU with
// Euler are stable at Courant 1 (one particle per cell): 30 steps, through the reflection at
// the free ends. DCU with Euler is not (limit 0.65): the fields are exact in exact arithmetic,
// but round-off in transverse modes grows about twice per step, so it is checked over 15 steps.
// CTU with RK2 is not exact: RK2's second stage sees a top/bottom pattern inside each cell (left
// by the first stage's transverse corrections) whose y-edge fluctuations correct the x-edge
// fluxes; its limit is below 1 (tests/lib_plane_strain.cpp).
BOOST_AUTO_TEST_CASE(blocks_meeting_give_the_1d_p_wave_solution) {
  for (int axis = 0; axis < 2; ++axis) {
    BOOST_TEST_CONTEXT("axis " << axis) {
      check_blocks(axis, false, "dcu", "rk2", 30);
      check_blocks(axis, false, "ctu", "euler", 30);
      check_blocks(axis, false, "dcu", "euler", 15);
    }
  }
}

// The same with tangential velocities: an S wave, exact at c_s dt / dx = 1, that is a Courant
// number c_p / c_s = 1.87 in c_p. The P family stays at zero up to round-off, which that Courant
// number amplifies (it is above the P waves' limit of 1), so 8 steps are checked.
BOOST_AUTO_TEST_CASE(blocks_sliding_give_the_1d_s_wave_solution) {
  for (int axis = 0; axis < 2; ++axis)
    for (const auto& [flux, integrator] :
         {std::pair{"dcu", "euler"}, std::pair{"dcu", "rk2"}, std::pair{"ctu", "euler"}}) {
      BOOST_TEST_CONTEXT("axis " << axis << ", " << flux << ", " << integrator) {
        check_blocks(axis, true, flux, integrator, 8);
      }
    }
}

// A roller edge is a symmetry plane: the plate with a roller bottom edge loaded on [0, 1] m of
// its left edge equals each half of a plate twice as high loaded on its middle 2 m: the upper
// half translated, the lower half mirrored (v_y and sigma_xy change sign).
BOOST_AUTO_TEST_CASE(roller_edge_is_a_symmetry_plane) {
  struct Case {
    const char* flux;
    const char* integrator;
    double courant;
  };
  for (const Case& c : {Case{"dcu", "rk2", 1.0}, Case{"ctu", "euler", 1.0}, Case{"ctu", "rk2", 0.7},
                        Case{"dcu", "euler", 0.6}}) {
    BOOST_TEST_CONTEXT(c.flux << ", " << c.integrator) {
      const double end = 8e-4;
      PlaneStrainSimulation half(
          scene::parse_scene(plate(c.flux, c.integrator, c.courant, end, true)));
      PlaneStrainSimulation full(
          scene::parse_scene(plate(c.flux, c.integrator, c.courant, end, false, 6.0, 2.0, 4.0)));
      half.advance_to(end);
      full.advance_to(end);
      BOOST_REQUIRE(half.steps() == full.steps());
      const auto sh = half.physical_state(), sf = full.physical_state();
      const auto &xh = half.particles().position, &xf = full.particles().position;
      const double scale = 2e8;
      double err = 0;
      int matched = 0;
      for (int q = 0; q < full.particles().size(); ++q) {
        const bool upper = xf(1, q) > 3.0;
        const double y = upper ? xf(1, q) - 3.0 : 3.0 - xf(1, q);
        for (int p = 0; p < half.particles().size(); ++p) {
          if (std::abs(xh(0, p) - xf(0, q)) > 1e-9 || std::abs(xh(1, p) - y) > 1e-9) continue;
          ++matched;
          for (int k = 0; k < PS::n_comp; ++k) {
            const double sign = !upper && (k == PS::vy || k == PS::sxy) ? -1.0 : 1.0;
            const double unit = k >= PS::vx ? scale / steel.p_impedance() : scale;
            err = std::max(err, std::abs(sf(k, q) - sign * sh(k, p)) / unit);
          }
        }
      }
      BOOST_TEST(matched == full.particles().size());
      BOOST_TEST(err < 1e-10, "largest difference " << err);
      BOOST_TEST(sh.row(PS::sxx).cwiseAbs().maxCoeff() > 0.5 * scale);  // the wave is there
    }
  }
}

// Energy: the kinetic and elastic energy of the plate never exceeds the work done by the load;
// with no load and free edges, a moving block's energy never grows.
BOOST_AUTO_TEST_CASE(energy_stays_below_the_work_of_the_load) {
  for (const auto& [flux, integrator] : {std::pair{"dcu", "rk2"}, std::pair{"ctu", "euler"}}) {
    BOOST_TEST_CONTEXT(flux << ", " << integrator) {
      PlaneStrainSimulation sim(scene::parse_scene(plate(flux, integrator, 1.0, 1.2e-3, false)));
      double worst = -1;
      while (sim.time() < 1.2e-3 * (1 - 1e-12)) {
        sim.step(std::min(sim.stable_time_step(), 1.2e-3 - sim.time()));
        worst = std::max(worst, sim.energy() / sim.boundary_work());
        BOOST_REQUIRE(sim.boundary_work() > 0);
      }
      BOOST_TEST(worst <= 1.0, "largest energy / work " << worst);
      BOOST_TEST(worst > 0.5);  // the load's work went somewhere

      json doc = plate(flux, integrator, 1.0, 1e-3, false);
      doc.erase("boundaries");
      doc["bodies"][0]["velocity"] = {3.0, -2.0};
      doc["bodies"][0]["box"] = {{"min", {0.0, 0.0}}, {"max", {2.0, 1.5}}};  // void around it
      PlaneStrainSimulation free(scene::parse_scene(doc));
      double e = free.energy();
      const double e0 = e;
      for (int s = 0; s < 200; ++s) {
        free.step(free.stable_time_step());
        BOOST_TEST(free.energy() <= e * (1 + 1e-12));
        e = free.energy();
      }
      BOOST_TEST(e < e0);  // the scheme's upwind dissipation
    }
  }
}

// A traction on [0, 1] m of the left edge, whose cells are 0.12 m high: the ninth cell edge is a
// third covered. The applied force is exact: the x-momentum gained per step is 2e8 N per m of
// thickness times dt, for DGMPM (each flux and integrator) and for MPM.
BOOST_AUTO_TEST_CASE(a_partly_covered_edge_receives_the_exact_force) {
  for (const char* method : {"dgmpm", "mpm-usl", "mpm-usf", "mpm-musl"})
    for (const char* flux : {"dcu", "ctu"})
      for (const char* integrator : {"euler", "rk2"}) {
        const bool dg = std::string(method) == "dgmpm";
        if (!dg && (std::string(flux) == "ctu" || std::string(integrator) == "rk2")) continue;
        BOOST_TEST_CONTEXT(method << ", " << flux << ", " << integrator) {
          json doc = plate(flux, integrator, 0.5, 1e-3, false);
          doc["method"] = method;
          if (!dg) {
            doc.erase("flux");
            doc["time"].erase("integrator");
          }
          PlaneStrainSimulation sim(scene::parse_scene(doc));
          const double dt = sim.stable_time_step();
          for (int s = 0; s < 5; ++s) sim.step(dt);
          BOOST_TEST(momentum(sim, 0).sum() == 5 * dt * 2e8, boost::test_tools::tolerance(1e-12));
          BOOST_TEST(std::abs(momentum(sim, 1).sum()) < 1e-12 * 5 * dt * 2e8);
        }
      }
}

// Velocity and fixed edges: a block at rest driven at v0 along x by its left edge, and a block
// moving at -v0 along y into a fixed bottom edge: the P plateau sigma_nn = -Z_p v0 (with
// sigma_tt = lambda / (lambda + 2 mu) sigma_nn), exact at c_p dt / dx = 1 behind the front.
BOOST_AUTO_TEST_CASE(velocity_and_fixed_edges_give_the_1d_plateaus) {
  const double v0 = 4.0, h = 0.1, z = steel.p_impedance();
  for (const auto& [flux, integrator] : {std::pair{"dcu", "rk2"}, std::pair{"ctu", "euler"}})
    for (int axis = 0; axis < 2; ++axis) {
      BOOST_TEST_CONTEXT(flux << ", " << integrator << ", axis " << axis) {
        json doc = blocks(axis, false, 10, 3, flux, integrator, 1.0, 1.0);
        doc["bodies"].erase(1);
        doc["bodies"][0]["box"]["max"][axis] = 2.0;
        json v = {0.0, 0.0};
        const char* side = axis == 0 ? "xmin" : "ymin";
        if (axis == 0) {
          v[0] = v0;  // driven edge, body at rest
          doc["boundaries"] = {{side, {{"type", "velocity"}, {"value", v}}}};
          doc["bodies"][0]["velocity"] = {0.0, 0.0};
        } else {
          doc["boundaries"] = {{side, {{"type", "fixed"}}}};
          v[1] = -v0;  // moving into the wall
          doc["bodies"][0]["velocity"] = v;
        }
        PlaneStrainSimulation sim(scene::parse_scene(doc));
        const int steps = 12;
        for (int k = 0; k < steps; ++k) sim.step(h / steel.p_speed());
        const auto st = sim.physical_state();
        const auto& x = sim.particles().position;
        const int nn = axis == 0 ? PS::sxx : PS::syy, tt = axis == 0 ? PS::syy : PS::sxx;
        double err = 0;
        for (int p = 0; p < sim.particles().size(); ++p) {
          const bool behind = x(axis, p) < steps * h;
          const double s_exact = behind ? -z * v0 : 0.0;
          const double v_exact = axis == 0 ? (behind ? v0 : 0.0) : (behind ? 0.0 : -v0);
          err = std::max(
              {err, std::abs(st(nn, p) - s_exact) / (z * v0),
               std::abs(st(tt, p) - steel.lambda() / steel.p_modulus() * s_exact) / (z * v0),
               std::abs(st(PS::vx + axis, p) - v_exact) / v0});
        }
        BOOST_TEST(err < 1e-10, "max relative error " << err);
      }
    }
}

// A traction given as a time table, normal and shear: the momentum gained is the impulse of the
// table as each integrator samples it (Euler at t_n; RK2 the mean of t_n and t_n + dt).
BOOST_AUTO_TEST_CASE(traction_time_tables_deliver_their_impulse) {
  const double ramp = 1e-4, normal = -2e8, shear = 5e7;
  const auto table = [&](double t) { return std::min(t, ramp) / ramp; };
  for (const char* integrator : {"euler", "rk2"}) {
    BOOST_TEST_CONTEXT(integrator) {
      json doc = plate("dcu", integrator, 0.5, 1e-3, false);
      doc["boundaries"]["xmin"][0]["value"] = {{0.0, {0.0, 0.0}}, {ramp, {normal, shear}}};
      PlaneStrainSimulation sim(scene::parse_scene(doc));
      const double dt = sim.stable_time_step();
      double impulse = 0;
      for (int k = 0; k < 8; ++k) {
        const double t = k * dt;
        impulse += std::string(integrator) == "euler" ? dt * table(t)
                                                      : 0.5 * dt * (table(t) + table(t + dt));
        sim.step(dt);
      }
      // The left edge's outward normal is -x: the body receives -sigma e_x per metre loaded.
      BOOST_TEST(momentum(sim, 0).sum() == -normal * impulse, boost::test_tools::tolerance(1e-11));
      BOOST_TEST(momentum(sim, 1).sum() == -shear * impulse, boost::test_tools::tolerance(1e-11));
    }
  }
}

// MPM runs the 2D plate: finite fields of the right order (the loaded corner near -2e8 Pa).
BOOST_AUTO_TEST_CASE(mpm_runs_the_plate) {
  for (const char* method : {"mpm-usl", "mpm-usf", "mpm-musl"}) {
    BOOST_TEST_CONTEXT(method) {
      json doc = plate("dcu", "euler", 0.5, 3e-4, false);
      doc["method"] = method;
      doc.erase("flux");
      doc["time"].erase("integrator");
      PlaneStrainSimulation sim(scene::parse_scene(doc));
      sim.advance_to(3e-4);
      const auto s = sim.physical_state();
      BOOST_TEST(s.allFinite());
      BOOST_TEST(s.row(PS::sxx).minCoeff() < -1e8);
      BOOST_TEST(s.row(PS::sxx).minCoeff() > -4e8);
    }
  }
}

namespace {

std::string refusal(const json& doc) {
  try {
    const scene::Scene s = scene::parse_scene(doc, "scene.json");
    if (s.dimension == 2) PlaneStrainSimulation sim(s);
    return "";
  } catch (const scene::SceneError& e) {
    return e.what();
  }
}

void check_refused(const json& doc, const std::vector<std::string>& parts) {
  const std::string message = refusal(doc);
  BOOST_TEST(!message.empty(), "accepted: " << doc.dump());
  for (const auto& part : parts)
    BOOST_TEST(message.find(part) != std::string::npos, "'" << part << "' not in: " << message);
}

}  // namespace

BOOST_AUTO_TEST_CASE(refuses_bad_2d_inputs) {
  const json good = plate("dcu", "rk2", 1.0, 1e-3, false);
  BOOST_TEST(refusal(good).empty());
  json d = good;
  d["boundaries"]["xmin"].push_back({{"type", "velocity"}, {"value", {1, 0}}, {"range", {0.5, 2}}});
  check_refused(d, {"boundaries.xmin[1].range: value [0.5,2] overlaps boundaries.xmin[0].range",
                    "do not overlap"});
  d = good;
  d["boundaries"]["xmin"][0]["range"] = {2.5, 3.5};
  check_refused(d, {"boundaries.xmin[0].range: value [2.5,3.5] is outside", "[0, 3]"});
  d["boundaries"]["xmin"][0]["range"] = {1.0, 0.5};
  check_refused(d, {"boundaries.xmin[0].range: value [1.0,0.5] is empty or reversed"});
  d = good;
  d["boundaries"]["xmin"][0].erase("range");
  d["boundaries"]["xmin"].push_back({{"type", "free"}, {"range", {2, 3}}});
  check_refused(d, {"boundaries.xmin[0].range: missing required key"});
  d = good;
  d["boundaries"]["xmin"][0]["value"] = {-2e8};
  check_refused(
      d, {"boundaries.xmin[0].value: value [-200000000.0] has 1 entries", "sigma_xx, sigma_xy"});
  d["boundaries"]["xmin"][0]["value"] = {{0.0, {-2e8, 0, 1}}};
  check_refused(d, {"boundaries.xmin[0].value[0][1]: value", "has 3 entries"});
  d = good;
  d["boundaries"]["ymax"] = {{"type", "velocity"}, {"value", 5.0}};
  check_refused(d, {"boundaries.ymax.value: value 5.0 has the wrong type", "[v_x, v_y]"});
  d = good;
  d["boundaries"]["ymax"] = {{"type", "roller"}, {"value", {0, 0}}};
  check_refused(d, {"boundaries.ymax.value: value [0,0] is not allowed with type \"roller\""});
  d = good;
  d["boundaries"]["xmax"] = json::array();
  check_refused(d, {"boundaries.xmax: value [] holds no segment"});
  d = good;
  d["flux"] = "muscl";
  check_refused(d, {"flux: value \"muscl\" is not known", "dcu, ctu"});
  d = good;
  d["method"] = "mpm-usl";
  check_refused(d, {"flux: value \"dcu\" is not allowed with 2D method \"mpm-usl\""});
  d = good;
  d["grid"]["periodic"] = {true};
  check_refused(d, {"grid.periodic: value [true] has 1 entries", "2 booleans"});
  d = good;
  d["grid"]["periodic"] = {true, false};
  check_refused(d, {"boundaries.xmin: value", "is not allowed on a periodic axis"});
  d = good;
  d["bodies"][0]["particles_per_cell"] = {9, 9};
  check_refused(d, {"bodies[0].particles_per_cell: value [9,9] makes 81 particles per cell"});
  d["bodies"][0]["particles_per_cell"] = {1, 1, 1};
  check_refused(d, {"bodies[0].particles_per_cell: value [1,1,1] has 3 entries"});
  d = good;
  d["bodies"][0].erase("particles_per_cell");
  d["bodies"][0]["positions_in_cell"] = {{0.25, 0.5}, {0.75}};
  check_refused(d, {"bodies[0].positions_in_cell[1]: value [0.75] has 1 entries"});
  d["bodies"][0]["positions_in_cell"] = {{0.25, 1.5}};
  check_refused(d, {"bodies[0].positions_in_cell[0][1]: value 1.5 is not allowed", "[0, 1]"});
  d = good;
  d["bodies"][0]["stress"] = {0, 0};
  check_refused(d, {"bodies[0].stress: value [0,0] has 2 entries", "3 numbers"});
  d = good;
  d["bodies"][0]["velocity"] = {1};
  check_refused(d, {"bodies[0].velocity: value [1] has 1 entries", "2 numbers"});
  d = good;
  d["exact"] = "bar";
  check_refused(d, {"exact: value \"bar\""});
  d = good;
  d["output"] = {{"formats", {"csv", "png"}}};
  check_refused(d, {"output.formats[1]: value \"png\" is not known", "csv, vtu"});

  // 1D: no flux key, no roller, no ranges.
  json bar = {{"dimension", 1},
              {"grid", {{"origin", {0.0}}, {"cell_size", {0.1}}, {"cells", {10}}}},
              {"materials", {{"steel", {{"young", young}, {"density", rho}}}}},
              {"bodies",
               {{{"material", "steel"},
                 {"box", {{"min", {0.0}}, {"max", {1.0}}}},
                 {"particles_per_cell", 1}}}},
              {"time", {{"end", 1e-4}}}};
  BOOST_TEST(refusal(bar).empty());
  json b = bar;
  b["flux"] = "ctu";
  check_refused(b, {"flux: value \"ctu\" is not allowed with 1D method \"dgmpm\""});
  b = bar;
  b["boundaries"] = {{"xmin", {{"type", "roller"}}}};
  check_refused(b, {"boundaries.xmin.type: value \"roller\" is not known"});
  b["boundaries"] = {{"xmin", {{"type", "free"}, {"range", {0, 1}}}}};
  check_refused(b, {"boundaries.xmin.range: unknown key"});
}
