// Solids that yield, through the solver: the shipped plastic bar impact against the exact plateau
// of its elastic-plastic wave pair (DGMPM Euler and RK2, fixed and moving particles, and the MPM
// baseline's three variants), the energy balance at every step, a stiff Perzyna relaxation at
// the elastic time step, elastic and plastic materials side by side, and the scene's errors; in
// 2D the uniaxial-strain strip (plane strain, periodic along y) against its exact plateau and an
// independent finite-volume code's, with sigma_zz tracked through the returns.
#define BOOST_TEST_MODULE solver_plasticity
#include <boost/test/unit_test.hpp>

#include "solver/problem.hpp"
#include "solver/scene.hpp"
#include "solver/simulation.hpp"

#include <nlohmann/json.hpp>

#include <algorithm>
#include <cmath>
#include <fstream>
#include <limits>
#include <string>
#include <utility>
#include <vector>

using namespace dgmpm;
using nlohmann::json;

namespace {

constexpr double E = 2e11, rho = 7800, sigma_y = 4e8, c_kin = 15e9, v0 = 30.55;

json shipped() {
  std::ifstream in(std::string(DGMPM_TEST_SOURCE_DIR) + "/scenes/bar_plastic_impact.json");
  return json::parse(in);
}

// The exact plateau between the plastic fronts (uniaxial stress, linear kinematic hardening).
double plateau() {
  const double c = std::sqrt(E / rho), et = E * c_kin / (E + c_kin), cp = std::sqrt(et / rho);
  return sigma_y * (1 - cp / c) + rho * cp * v0;
}
double plastic_speed() {
  return std::sqrt(E * c_kin / (E + c_kin) / rho);
}

struct Result {
  double mean_stress = 0, mean_plastic_strain = 0;  // over the plateau's particles
  long steps = 0;
  bool balanced = true;  // total energy <= initial at every step
  double dissipated = 0, stored = 0;
};

// Steps the scene to its end, checking the energy at every step, and averages over the particles
// well inside the plastic fronts (the first-order fronts spread over about 0.3 m by then).
Result run(const json& doc) {
  Simulation<ElastoPlasticBar> sim(scene::parse_scene(doc));
  const double e0 = sim.energy(), t_end = doc["time"]["end"].get<double>();
  Result r;
  while (sim.time() < t_end) {
    sim.advance_to(std::min(t_end, sim.time() + sim.stable_time_step()));
    r.balanced = r.balanced && sim.energy() <= e0 * (1 + 1e-12);
  }
  r.steps = sim.steps();
  const auto& p = sim.particles();
  int count = 0;
  for (int i = 0; i < p.size(); ++i) {
    if (std::abs(p.position(0, i) - 3.0) > 0.3 * plastic_speed() * sim.time()) continue;
    r.mean_stress += -p.state(0, i) * rho;
    r.mean_plastic_strain += -p.internal(ElastoPlasticBar::plastic_strain, i);
    ++count;
  }
  BOOST_TEST_REQUIRE(count > 5);
  r.mean_stress /= count;
  r.mean_plastic_strain /= count;
  r.dissipated = sim.energy_parts().dissipated;
  r.stored = sim.energy_parts().stored;
  return r;
}

}  // namespace

BOOST_AUTO_TEST_CASE(the_shipped_impact_reaches_the_exact_plateau_by_every_route) {
  const double exact = plateau();
  for (const std::string method : {"dgmpm", "mpm-usl", "mpm-usf", "mpm-musl"})
    for (const std::string integrator : {"euler", "rk2"})
      for (const bool move : {false, true}) {
        if (method != "dgmpm" && (integrator == "rk2" || move)) continue;
        json doc = shipped();
        doc["method"] = method;
        doc["time"]["integrator"] = integrator;
        doc["particles_move"] = move;
        if (method != "dgmpm") doc["time"]["courant"] = 0.5;
        BOOST_TEST_CONTEXT(method << ", " << integrator << (move ? ", moving" : ", fixed")) {
          const Result r = run(doc);
          if (method == "dgmpm") BOOST_TEST(r.balanced);  // MPM makes no such promise
          BOOST_TEST(r.dissipated > 0);
          BOOST_TEST(r.stored > 0);
          // DGMPM's plateau: at Courant 1 (auto, one centred particle per cell) an odd-even
          // ripple of 0.2-0.4% that the scheme does not damp rides on it; MPM's oscillates more.
          // USF and MUSL pile up 9% too much plastic strain near the impact plane.
          const bool dg = method == "dgmpm";
          BOOST_TEST(r.mean_stress == exact, boost::test_tools::tolerance(dg ? 2e-3 : 2e-2));
          BOOST_TEST(r.mean_plastic_strain == (exact - sigma_y) / c_kin,
                     boost::test_tools::tolerance(dg ? 1e-2 : 0.15));
        }
      }
}

// tau = 1e-12 s, a million times below the time step: the run takes the elastic steps, stays
// bounded and lands on the rate-independent plateau (its distance, like tau^(1/n), is 2e-3 here).
BOOST_AUTO_TEST_CASE(a_stiff_relaxation_runs_at_the_elastic_time_step) {
  const Result plastic = run(shipped());
  json doc = shipped();
  auto& steel = doc["materials"]["steel"];
  steel["model"] = "elasto_viscoplastic";
  steel["relaxation_time"] = 1e-12;
  steel["rate_exponent"] = 4.37;
  const Result viscous = run(doc);
  BOOST_TEST(viscous.steps == plastic.steps);
  BOOST_TEST(viscous.balanced);
  BOOST_TEST(viscous.mean_stress > plastic.mean_stress);  // the overstress keeps it above
  BOOST_TEST(viscous.mean_stress == plastic.mean_stress, boost::test_tools::tolerance(1e-2));
  // A slow relaxation (tau = 1e6 s, dp / dt = (f / sigma_y)^n / tau about 2e-5 / s): hardly any
  // plastic flow, the elastic impact's stress rho c v0.
  steel["relaxation_time"] = 1e6;
  const Result slow = run(doc);
  BOOST_TEST(slow.mean_plastic_strain < 1e-8);
  BOOST_TEST(slow.mean_stress == rho * std::sqrt(E / rho) * v0, boost::test_tools::tolerance(1e-3));
}

BOOST_AUTO_TEST_CASE(elastic_and_plastic_materials_share_a_scene) {
  json doc = shipped();
  doc["materials"]["rubber"] = {{"model", "linear_elastic"}, {"young", 2e11}, {"density", 7800}};
  doc["bodies"][1]["material"] = "rubber";  // the right half never yields
  const scene::Scene scene = scene::parse_scene(doc);
  bool plastic_physics = false;
  with_physics(scene, [&](auto physics) {
    plastic_physics = std::is_same_v<typename decltype(physics)::type, ElastoPlasticBar>;
  });
  BOOST_TEST(plastic_physics);
  Simulation<ElastoPlasticBar> sim(scene);
  const double e0 = sim.energy();
  sim.advance_to(4e-4);
  BOOST_TEST(sim.energy() <= e0);
  const auto& p = sim.particles();
  double left = 0, right = 0;
  for (int i = 0; i < p.size(); ++i)
    (p.position(0, i) < 3.0 ? left : right) += std::abs(p.internal(0, i));
  BOOST_TEST(left > 0);
  BOOST_TEST(right == 0.0);
}

BOOST_AUTO_TEST_CASE(plastic_materials_are_checked_with_their_keys) {
  const auto message = [](const json& doc) {
    try {
      scene::parse_scene(doc, "s.json");
    } catch (const scene::SceneError& e) {
      return std::string(e.what());
    }
    return std::string("accepted");
  };
  const auto with = [](const std::string& key, const json& value) {
    json doc = shipped();
    if (value.is_null())
      doc["materials"]["steel"].erase(key);
    else
      doc["materials"]["steel"][key] = value;
    return doc;
  };
  const auto contains = [](const std::string& text, const std::string& part) {
    return text.find(part) != std::string::npos;
  };
  std::string m = message(with("yield_stress", nullptr));
  BOOST_TEST(contains(m, "materials.steel.yield_stress: missing required key"), m);
  m = message(with("yield_stress", -1.0));
  BOOST_TEST(contains(m, "materials.steel.yield_stress: value -1"), m);
  m = message(with("kinematic_hardening", -5.0));
  BOOST_TEST(
      contains(m, "materials.steel.kinematic_hardening: value -5.0 is not allowed: softening"), m);
  BOOST_TEST(contains(m, "allowed: a number >= 0 (Pa)"), m);
  m = message(with("relaxation_time", 1e-6));  // not an elastoplastic key
  BOOST_TEST(contains(m, "materials.steel.relaxation_time: unknown key"), m);
  json viscous = with("model", "elasto_viscoplastic");
  m = message(viscous);
  BOOST_TEST(contains(m, "materials.steel.relaxation_time: missing required key"), m);
  viscous["materials"]["steel"]["relaxation_time"] = 1e-6;
  viscous["materials"]["steel"]["rate_exponent"] = 0.5;
  m = message(viscous);
  BOOST_TEST(contains(m, "materials.steel.rate_exponent: value 0.5 is not allowed"), m);
  json wave = {
      {"dimension", 2},
      {"grid", {{"origin", {0, 0}}, {"cell_size", {1, 1}}, {"cells", {4, 4}}, {"periodic", true}}},
      {"materials", shipped()["materials"]},
      {"bodies",
       {{{"material", "steel"},
         {"box", {{"min", {0, 0}}, {"max", {4, 4}}}},
         {"particles_per_cell", {1, 1}}}}},
      {"plane_wave", {{"wave", "p"}, {"cycles", {1, 0}}, {"amplitude", 1.0}}},
      {"time", {{"end", 1e-4}}}};
  wave["materials"]["steel"]["poisson"] = 0.3;
  m = "accepted";
  try {
    make_simulation(scene::parse_scene(wave, "s.json"));
  } catch (const scene::SceneError& e) {
    m = e.what();
  }
  BOOST_TEST(contains(m, "plane_wave: cannot be used here: the plane wave is elastic"), m);
  json exact = shipped();
  exact["exact"] = "bar";
  BOOST_CHECK_THROW(make_simulation(scene::parse_scene(exact)), scene::SceneError);
}

namespace {

json shipped_strip() {
  std::ifstream in(std::string(DGMPM_TEST_SOURCE_DIR) + "/scenes/strip_plastic_impact.json");
  return json::parse(in);
}

// A front of the left half's |sigma_xx| profile (x ascending): where it first reaches the middle
// of a jump from `low` to `high`, and its width (from 10% to 90% of the jump).
struct Front {
  double position = 0, width = 0;
};
Front find_front(const std::vector<std::pair<double, double>>& profile, double low, double high) {
  const auto crossing = [&](double fraction) {
    const double level = low + fraction * (high - low);
    for (std::size_t k = 1; k < profile.size(); ++k)
      if (profile[k].second >= level) {
        const auto [x0, s0] = profile[k - 1];
        const auto [x1, s1] = profile[k];
        return s1 == s0 ? x1 : x0 + (level - s0) / (s1 - s0) * (x1 - x0);
      }
    return std::numeric_limits<double>::quiet_NaN();
  };
  return {crossing(0.5), crossing(0.9) - crossing(0.1)};
}

struct StripResult {
  double sigma_xx = 0, eps_p_xx = 0;  // plateau means (|x - 3| < 1.5 m)
  double zz_mismatch = 0;             // max |sigma_yy - sigma_zz| / max |sigma_xx|
  bool balanced = true;
  std::vector<std::pair<double, double>> profile;  // (x, |sigma_xx|) of the left half, x ascending
  double time = 0;
};

template <class Physics>
StripResult run_strip(const json& doc) {
  Simulation<Physics> sim(scene::parse_scene(doc));
  const double e0 = sim.energy(), t_end = doc["time"]["end"].get<double>();
  StripResult r;
  while (sim.time() < t_end) {
    sim.advance_to(std::min(t_end, sim.time() + sim.stable_time_step()));
    r.balanced = r.balanced && sim.energy() <= e0 * (1 + 1e-12);
  }
  const auto& p = sim.particles();
  const auto s = sim.physical_state();
  int count = 0;
  double largest = 0, mismatch = 0;
  for (int i = 0; i < p.size(); ++i) {
    const auto& m = sim.problem().materials[p.material[i]];
    const double zz = Physics::sigma_zz(s.col(i), m, p.internal.col(i));
    largest = std::max(largest, std::abs(s(0, i)));
    mismatch = std::max(mismatch, std::abs(s(1, i) - zz));
    if (p.position(0, i) < 3.0) r.profile.emplace_back(p.position(0, i), -s(0, i));
    if (std::abs(p.position(0, i) - 3.0) >= 1.5) continue;
    r.sigma_xx += -s(0, i);
    r.eps_p_xx += -p.internal(0, i);
    ++count;
  }
  BOOST_TEST_REQUIRE(count > 20);
  r.sigma_xx /= count;
  r.eps_p_xx /= count;
  r.zz_mismatch = mismatch / largest;
  std::sort(r.profile.begin(), r.profile.end());
  r.time = sim.time();
  return r;
}

}  // namespace

// Renaud's thesis (ch. 4), uniaxial strain: an elastic precursor at Y_H = (lambda + 2 mu)
// sigma_y / (2 mu), then a plastic front at c_p = sqrt(H_T / rho), H_T = K + 4 mu h / (3 (3 mu +
// h)); between the plastic fronts |sigma_xx| = Y_H (1 - c_p / c) + rho c_p v0 and |eps_p_xx| =
// 2 mu (S - Y_H) / ((3 mu + h) H_T). An independent first-order finite-volume code gives plateau
// means 1.26110e9 Pa and 2.03228e-3 at 200 cells, Courant 0.9 (the strip's resolution).
BOOST_AUTO_TEST_CASE(the_uniaxial_strain_strip_reaches_the_exact_plateau_in_plane_strain) {
  const double nu = 0.3, lambda = E * nu / ((1 + nu) * (1 - 2 * nu)), mu = E / (2 * (1 + nu));
  const double h = c_kin, bulk = lambda + 2 * mu / 3;
  const double yh = (lambda + 2 * mu) * sigma_y / (2 * mu), c = std::sqrt((lambda + 2 * mu) / rho);
  const double ht = bulk + 4 * mu * h / (3 * (3 * mu + h)), cp = std::sqrt(ht / rho);
  const double plateau = yh * (1 - cp / c) + rho * cp * v0;
  const double eps_p = 2 * mu * (plateau - yh) / ((3 * mu + h) * ht);
  BOOST_TEST(plateau == 1.2610e9, boost::test_tools::tolerance(1e-4));  // the thesis's numbers
  BOOST_TEST(eps_p == 2.0308e-3, boost::test_tools::tolerance(1e-4));
  const StripResult r = run_strip<PlaneStrainPlastic>(shipped_strip());
  BOOST_TEST(r.balanced);
  BOOST_TEST(r.sigma_xx == plateau, boost::test_tools::tolerance(2e-4));
  BOOST_TEST(r.sigma_xx == 1.26110e9, boost::test_tools::tolerance(2e-4));
  BOOST_TEST(r.eps_p_xx == eps_p, boost::test_tools::tolerance(3e-3));
  BOOST_TEST(r.eps_p_xx == 2.03228e-3, boost::test_tools::tolerance(2e-3));
  // Uniaxial strain keeps sigma_yy = sigma_zz: the tracked sigma_zz says so to round-off (taking
  // nu (sigma_xx + sigma_yy) instead would be 27% off sigma_xx on the plateau).
  BOOST_TEST(r.zz_mismatch < 1e-12);
}

// The same strip by other routes: DCU with RK2 under "auto", moving particles, and the MPM
// baseline (USL): the plateau within their accuracy.
BOOST_AUTO_TEST_CASE(the_strip_by_other_routes) {
  const double exact = 1.26110e9;
  json rk2 = shipped_strip();
  rk2["flux"] = "dcu";
  rk2["time"]["integrator"] = "rk2";
  rk2["time"]["courant"] = "auto";
  rk2["particles_move"] = true;
  const StripResult a = run_strip<PlaneStrainPlastic>(rk2);
  BOOST_TEST(a.balanced);
  BOOST_TEST(a.sigma_xx == exact, boost::test_tools::tolerance(2e-3));
  json mpm = shipped_strip();
  mpm.erase("flux");
  mpm["method"] = "mpm-usl";
  mpm["time"]["courant"] = 0.5;
  const StripResult b = run_strip<PlaneStrainPlastic>(mpm);
  BOOST_TEST(b.sigma_xx == exact, boost::test_tools::tolerance(2e-2));
}

// A plate of two materials side by side, one yielding, loaded hard: the scene's physics is the
// plastic one, the elastic material never flows, and the energy stays below the initial energy
// plus the work of the load.
BOOST_AUTO_TEST_CASE(a_plate_of_plastic_and_elastic_steel) {
  json doc = {{"dimension", 2},
              {"flux", "ctu"},
              {"grid", {{"origin", {0, 0}}, {"cell_size", {0.1, 0.1}}, {"cells", {20, 10}}}},
              {"materials",
               {{"soft",
                 {{"model", "elasto_viscoplastic"},
                  {"young", E},
                  {"poisson", 0.3},
                  {"density", rho},
                  {"yield_stress", 1e8},
                  {"isotropic_hardening", 2e9},
                  {"relaxation_time", 1e-6},
                  {"rate_exponent", 2}}},
                {"hard", {{"young", E}, {"poisson", 0.3}, {"density", rho}}}}},
              {"bodies",
               {{{"material", "soft"},
                 {"box", {{"min", {0, 0}}, {"max", {1, 1}}}},
                 {"particles_per_cell", {2, 2}}},
                {{"material", "hard"},
                 {"box", {{"min", {1, 0}}, {"max", {2, 1}}}},
                 {"particles_per_cell", {1, 1}}}}},
              {"boundaries",
               {{"xmin", {{{"type", "traction"}, {"value", {-4e8, 1e8}}, {"range", {0.0, 0.5}}}}},
                {"ymin", {{"type", "roller"}}}}},
              {"time", {{"end", 4e-4}, {"integrator", "euler"}, {"courant", "auto"}}}};
  Simulation<PlaneStrainPlastic> sim(scene::parse_scene(doc));
  const double e0 = sim.energy();
  bool balanced = true;
  while (sim.time() < 4e-4) {
    sim.advance_to(std::min(4e-4, sim.time() + sim.stable_time_step()));
    balanced = balanced && sim.energy() <= (e0 + sim.boundary_work()) * (1 + 1e-9) + 1e-9;
  }
  BOOST_TEST(balanced);
  const auto& p = sim.particles();
  double soft = 0, hard = 0;
  for (int i = 0; i < p.size(); ++i)
    (sim.scene().materials[p.material[i]].name == "soft" ? soft : hard) +=
        p.internal(PlaneStrainPlastic::equivalent_plastic_strain, i);
  BOOST_TEST(soft > 0);
  BOOST_TEST(hard == 0.0);
  BOOST_TEST(sim.energy_parts().dissipated > 0);
}

namespace {

// The strip made viscoplastic (Perzyna, n = 4.37, tau = 2.2978e-4 s) at `cells` cells, Courant 1:
// the largest |sigma_xx| near the elastic front at time t.
double precursor_peak(int cells, double t) {
  json doc = shipped_strip();
  const double h = 6.0 / cells;
  doc["grid"]["cell_size"] = {h, h};
  doc["grid"]["cells"] = {cells, 2};
  for (auto& body : doc["bodies"]) body["box"]["max"][1] = 2 * h;
  doc["materials"]["steel"]["model"] = "elasto_viscoplastic";
  doc["materials"]["steel"]["relaxation_time"] = 2.2978e-4;
  doc["materials"]["steel"]["rate_exponent"] = 4.37;
  doc["time"]["courant"] = 1.0;
  doc["time"]["end"] = t;
  doc.erase("output");
  Simulation<PlaneStrainPlastic> sim(scene::parse_scene(doc));
  sim.advance_to(t);
  const double c = sim.problem().materials[0].p_speed(), front = 3.0 + c * t;
  const auto s = sim.physical_state();
  double peak = 0;
  for (int i = 0; i < s.cols(); ++i) {
    const double x = sim.particles().position(0, i);
    if (x > front - 6 * h && x < front + 2 * h) peak = std::max(peak, std::abs(s(0, i)));
  }
  return peak;
}

}  // namespace

// Perzyna in uniaxial strain: the elastic precursor starts at rho c v0 and decays toward Y_H; its
// jump is Y_H (1 + delta) with delta^(1-n) = delta0^(1-n) + (n - 1) mu t / (tau Y_H), delta0 =
// rho c v0 / Y_H - 1 (0.8260, 0.8118, 0.8014 GPa at t = 2e-4, 3e-4, 4.17e-4 s). At Courant 1 the
// front stays one cell sharp and its peak converges at first order: halving the cells halves the
// error, and the extrapolation of two resolutions lands within 1%.
BOOST_AUTO_TEST_CASE(a_viscoplastic_precursor_decays_as_the_exact_solution) {
  const double nu = 0.3, lambda = E * nu / ((1 + nu) * (1 - 2 * nu)), mu = E / (2 * (1 + nu));
  const double yh = (lambda + 2 * mu) * sigma_y / (2 * mu), c = std::sqrt((lambda + 2 * mu) / rho);
  const double n = 4.37, tau = 2.2978e-4, delta0 = rho * c * v0 / yh - 1;
  const auto exact = [&](double t) {
    const double d = std::pow(std::pow(delta0, 1 - n) + (n - 1) * mu * t / (tau * yh), 1 / (1 - n));
    return yh * (1 + d);
  };
  BOOST_TEST(exact(2e-4) == 0.8260e9, boost::test_tools::tolerance(1e-4));
  BOOST_TEST(exact(3e-4) == 0.8118e9, boost::test_tools::tolerance(1e-4));
  BOOST_TEST(exact(4.17e-4) == 0.8014e9, boost::test_tools::tolerance(1e-4));
  for (const double t : {3e-4, 4.17e-4}) {
    const double coarse = precursor_peak(400, t), fine = precursor_peak(800, t);
    const double e_coarse = coarse - exact(t), e_fine = fine - exact(t);
    BOOST_TEST_CONTEXT("t = " << t) {
      BOOST_TEST(e_fine > 0);
      BOOST_TEST(e_coarse / e_fine > 1.8);  // first order
      BOOST_TEST(2 * fine - coarse == exact(t), boost::test_tools::tolerance(1e-2));
    }
  }
}

// The uniaxial-strain wave by its two routes: the 1D physics ("strain": "uniaxial_strain", sigma_yy
// derived from sigma_xx and eps_p_xx at each particle) and the plane-strain strip (sigma_yy a
// field the DG step carries, sigma_zz through eps_p_zz). With one centred particle per cell the
// strip's nodal sigma_yy moves by lambda / (lambda + 2 mu) of sigma_xx's elastic increment and
// the return's mu d eps_p_xx, which is the 1D closed form's increment: the same steps give the
// same particles to round-off (DCU and CTU).
BOOST_AUTO_TEST_CASE(the_uniaxial_strain_wave_agrees_in_1d_and_as_a_2d_strip) {
  const json strip = shipped_strip();
  json bar = {{"dimension", 1},
              {"strain", "uniaxial_strain"},
              {"grid", {{"origin", {0.0}}, {"cell_size", {0.03}}, {"cells", {200}}}},
              {"materials", strip["materials"]},
              {"bodies",
               {{{"material", "steel"},
                 {"box", {{"min", {0.0}}, {"max", {3.0}}}},
                 {"particles_per_cell", 1},
                 {"velocity", {v0}}},
                {{"material", "steel"},
                 {"box", {{"min", {3.0}}, {"max", {6.0}}}},
                 {"particles_per_cell", 1},
                 {"velocity", {-v0}}}}},
              {"time", strip["time"]}};
  const scene::Scene one = scene::parse_scene(bar);
  bool uniaxial = false;
  with_physics(one, [&](auto physics) {
    uniaxial = std::is_same_v<typename decltype(physics)::type, UniaxialStrainPlastic>;
  });
  BOOST_TEST(uniaxial);
  Simulation<UniaxialStrainPlastic> a(one);
  Simulation<PlaneStrainPlastic> b(scene::parse_scene(strip));
  const double e0 = a.energy();
  a.advance_to(4.17e-4);
  b.advance_to(4.17e-4);
  BOOST_TEST(a.energy() <= e0);
  const auto sa = a.physical_state();
  const auto sb = b.physical_state();
  double largest = 0, xx = 0, yy = 0, eps = 0;
  for (int i = 0; i < sa.cols(); ++i) {
    // the strip's particle in the first row at the same x (its particles are sorted by cell)
    BOOST_TEST_REQUIRE(b.particles().position(0, i) == a.particles().position(0, i));
    const auto& m = a.problem().materials[0];
    const auto z = a.particles().internal.col(i);
    largest = std::max(largest, std::abs(sb(0, i)));
    xx = std::max(xx, std::abs(sa(0, i) - sb(0, i)));
    yy = std::max(yy, std::abs(UniaxialStrainPlastic::sigma_yy(sa(0, i), z, m) - sb(1, i)));
    eps = std::max(eps, std::abs(z[0] - b.particles().internal(PlaneStrainPlastic::exx, i)));
  }
  BOOST_TEST(xx < 1e-12 * largest);
  BOOST_TEST(yy < 1e-12 * largest);
  BOOST_TEST(eps < 1e-15);
  // Uniaxial strain is a 1D choice.
  json wrong = strip;
  wrong["strain"] = "uniaxial_strain";
  BOOST_CHECK_THROW(scene::parse_scene(wrong), scene::SceneError);
}

// With one centred particle per cell and Euler, DGMPM is the first-order Godunov finite-volume
// scheme followed by the return in each cell. Both written out here, independently of lib (cell
// averages, the acoustic Riemann solver, mirror ghosts at the free ends, the radial return with
// mixed hardening): the solver's bar matches them to round-off over 200 steps.
BOOST_AUTO_TEST_CASE(one_centred_particle_per_cell_is_godunov_then_the_return) {
  const double h_iso = 10e9, kin = 5e9, dx = 0.03, courant = 0.9;
  const int cells = 200;
  json doc = shipped();
  doc["grid"]["cell_size"] = {dx};
  doc["grid"]["cells"] = {cells};
  doc["materials"]["steel"]["isotropic_hardening"] = h_iso;
  doc["materials"]["steel"]["kinematic_hardening"] = kin;
  doc["time"]["courant"] = courant;
  doc.erase("output");
  Simulation<ElastoPlasticBar> sim(scene::parse_scene(doc));
  const double c = std::sqrt(E / rho), z = rho * c, dt = courant * dx / c;
  std::vector<double> s(cells, 0.0), v(cells), ep(cells, 0.0), p(cells, 0.0);
  for (int i = 0; i < cells; ++i) v[i] = i < cells / 2 ? v0 : -v0;
  std::vector<double> ss(cells + 1), vs(cells + 1);
  for (int step = 0; step < 200; ++step) {
    for (int f = 0; f <= cells; ++f) {  // face f between cells f - 1 and f; free ends mirror
      const double sl = f > 0 ? s[f - 1] : -s[0], vl = f > 0 ? v[f - 1] : v[0];
      const double sr = f < cells ? s[f] : -s[cells - 1], vr = f < cells ? v[f] : v[cells - 1];
      vs[f] = 0.5 * (vl + vr) + (sr - sl) / (2 * z);
      ss[f] = 0.5 * (sl + sr) + 0.5 * z * (vr - vl);
    }
    for (int i = 0; i < cells; ++i) {
      s[i] += dt / dx * E * (vs[i + 1] - vs[i]);
      v[i] += dt / (rho * dx) * (ss[i + 1] - ss[i]);
      const double xi = s[i] - kin * ep[i], f = std::abs(xi) - (sigma_y + h_iso * p[i]);
      if (f <= 0) continue;
      const double dp = f / (E + h_iso + kin), sign = xi > 0 ? 1.0 : -1.0;
      s[i] -= E * dp * sign;
      ep[i] += dp * sign;
      p[i] += dp;
    }
    sim.step(dt);
  }
  const auto state = sim.physical_state();
  double ds = 0, dv = 0, de = 0, yielded = 0;
  for (int i = 0; i < cells; ++i) {
    ds = std::max(ds, std::abs(state(0, i) - s[i]));
    dv = std::max(dv, std::abs(state(1, i) - v[i]));
    de = std::max(de, std::abs(sim.particles().internal(0, i) - ep[i]));
    yielded += p[i] > 0;
  }
  BOOST_TEST(yielded > 20);
  BOOST_TEST(ds < 1e-12 * 1e9);
  BOOST_TEST(dv < 1e-12 * v0);
  BOOST_TEST(de < 1e-15);
}

// Perzyna with n = 1 and tau far below the step is the rate-independent return to within
// tau / dt: at tau = 1e-12 s the runs agree to 1e-9.
BOOST_AUTO_TEST_CASE(a_linear_perzyna_law_with_a_tiny_relaxation_time_is_rate_independent) {
  json doc = shipped();
  doc.erase("output");
  Simulation<ElastoPlasticBar> plastic(scene::parse_scene(doc));
  doc["materials"]["steel"]["model"] = "elasto_viscoplastic";
  doc["materials"]["steel"]["relaxation_time"] = 1e-12;
  doc["materials"]["steel"]["rate_exponent"] = 1;
  Simulation<ElastoPlasticBar> viscous(scene::parse_scene(doc));
  plastic.advance_to(4e-4);
  viscous.advance_to(4e-4);
  BOOST_TEST(viscous.steps() == plastic.steps());
  const double largest = plastic.physical_state().row(0).cwiseAbs().maxCoeff();
  const double gap =
      (plastic.physical_state().row(0) - viscous.physical_state().row(0)).cwiseAbs().maxCoeff();
  BOOST_TEST(gap < 1e-9 * largest);
}

// Plastic scenes at 0.99 of the automatic step for 1e4 steps (the bar, its free ends reflecting
// the waves to and fro): the energy balance never grows.
BOOST_AUTO_TEST_CASE(ten_thousand_steps_at_the_automatic_step_keep_the_balance) {
  json doc = shipped();
  doc.erase("output");
  doc["grid"]["cell_size"] = {0.06};
  doc["grid"]["cells"] = {100};
  doc["materials"]["steel"]["isotropic_hardening"] = 2e9;
  doc["time"]["integrator"] = "rk2";
  doc["time"]["safety"] = 0.99;
  doc["time"]["end"] = 1.0;
  Simulation<ElastoPlasticBar> sim(scene::parse_scene(doc));
  double last = sim.energy();
  const double e0 = last;
  bool never_grows = true;
  for (int k = 0; k < 10000; ++k) {
    sim.step(sim.stable_time_step());
    const double e = sim.energy();
    never_grows = never_grows && e <= last * (1 + 1e-13) + 1e-12 * e0;
    last = e;
  }
  BOOST_TEST(never_grows);
  BOOST_TEST(sim.energy_parts().dissipated > 0);
}

// Every shipped scene with a material that yields: at every step the energy (kinetic, elastic,
// stored, dissipated) is at most the initial energy plus the work of the loads, and the run
// dissipates.
BOOST_AUTO_TEST_CASE(every_shipped_plastic_scene_keeps_the_energy_balance) {
  for (const std::string name : {"bar_plastic_impact", "strip_plastic_impact",
                                 "strip_viscoplastic_impact", "plate_plastic"}) {
    const scene::Scene scene =
        scene::load_scene(std::string(DGMPM_TEST_SOURCE_DIR) + "/scenes/" + name + ".json");
    with_physics(scene, [&](auto physics) {
      using P = typename decltype(physics)::type;
      if constexpr (physics::Dissipative<P>) {
        Simulation<P> sim(scene);
        const double e0 = sim.energy();
        bool balanced = true;
        while (sim.time() < scene.time.end) {
          sim.advance_to(std::min(scene.time.end, sim.time() + sim.stable_time_step()));
          balanced = balanced && sim.energy() <= (e0 + sim.boundary_work()) * (1 + 1e-9);
        }
        BOOST_TEST(balanced, name);
        BOOST_TEST(sim.energy_parts().dissipated > 0, name);
      } else {
        BOOST_FAIL(name << ": not a plastic physics");
      }
    });
  }
}

// The strip's y-direction twin (the same wave along y, periodic along x): the same particles with
// x and y (and the stress components) swapped, to round-off.
BOOST_AUTO_TEST_CASE(the_strip_along_y_is_the_strip_along_x_transposed) {
  const json strip = shipped_strip();
  json twin = strip;
  twin["grid"]["cells"] = {2, 200};
  twin["grid"]["periodic"] = {true, false};
  twin.erase("boundaries");
  twin["boundaries"] = {{"ymin", {{"type", "free"}}}, {"ymax", {{"type", "free"}}}};
  for (auto& body : twin["bodies"]) {
    const json lo = body["box"]["min"], hi = body["box"]["max"], v = body["velocity"];
    body["box"]["min"] = {lo[1], lo[0]};
    body["box"]["max"] = {hi[1], hi[0]};
    body["velocity"] = {v[1], v[0]};
  }
  Simulation<PlaneStrainPlastic> a(scene::parse_scene(strip)), b(scene::parse_scene(twin));
  a.advance_to(4.17e-4);
  b.advance_to(4.17e-4);
  const auto sa = a.physical_state(), sb = b.physical_state();
  const auto& pa = a.particles();
  const auto& pb = b.particles();
  BOOST_TEST_REQUIRE(pa.size() == pb.size());
  double largest = 0, difference = 0;
  int matched = 0;
  for (int i = 0; i < pa.size(); ++i)
    for (int j = 0; j < pb.size(); ++j) {
      if (pb.position(0, j) != pa.position(1, i) || pb.position(1, j) != pa.position(0, i))
        continue;
      ++matched;
      largest = std::max(largest, std::abs(sa(0, i)));
      difference = std::max({difference, std::abs(sa(0, i) - sb(1, j)),
                             std::abs(sa(1, i) - sb(0, j)), std::abs(sa(3, i) - sb(4, j))});
      BOOST_TEST(std::abs(pa.internal(PlaneStrainPlastic::exx, i) -
                          pb.internal(PlaneStrainPlastic::eyy, j)) < 1e-15);
    }
  BOOST_TEST(matched == pa.size());
  BOOST_TEST(difference <= 1e-12 * largest);
}

// The strip at other resolutions and with two particles per cell along x (Courant 0.5, within
// their limit): the plateau means of |sigma_xx| and |eps_p_xx| (|x - 3| < 1.5 m) against the exact
// 1.2610 GPa and 2.0308e-3. Measured: 50 cells 2.7e-4 and 2.4e-3 (the cells at the impact plane
// carry a start-up error of about 1% in eps_p, a larger share of the plateau at 50 cells), 800
// cells 1.9e-5 and 4.9e-4, 2 particles per cell at 200 cells 1.5e-4 and 5.6e-3. At 50 cells the
// plateau is not flat (eps_p rises by 1.2% from the plastic front's foot to the impact plane), so
// its mean depends on the window: 16 cells +6.2e-3, 24 (this window) +2.4e-3, 26 -2.1e-3.
BOOST_AUTO_TEST_CASE(the_strip_converges_and_runs_with_two_particles_per_cell) {
  const auto strip = [](int cells, int ppc) {
    json doc = shipped_strip();
    const double h = 6.0 / cells;
    doc["grid"]["cell_size"] = {h, h};
    doc["grid"]["cells"] = {cells, 2};
    for (auto& body : doc["bodies"]) {
      body["box"]["max"][1] = 2 * h;
      body["particles_per_cell"] = {ppc, 1};
    }
    if (ppc > 1) doc["time"]["courant"] = 0.5;
    doc.erase("output");
    return run_strip<PlaneStrainPlastic>(doc);
  };
  const double sigma = 1.2610e9, eps = 2.0308e-3;
  const StripResult coarse = strip(50, 1), fine = strip(800, 1), two = strip(200, 2);
  BOOST_TEST(coarse.sigma_xx == sigma, boost::test_tools::tolerance(2e-3));
  BOOST_TEST(coarse.eps_p_xx == eps, boost::test_tools::tolerance(3e-3));
  BOOST_TEST(fine.sigma_xx == sigma, boost::test_tools::tolerance(1e-4));
  BOOST_TEST(fine.eps_p_xx == eps, boost::test_tools::tolerance(6e-4));
  BOOST_TEST(two.sigma_xx == sigma, boost::test_tools::tolerance(1e-3));
  BOOST_TEST(two.eps_p_xx == eps, boost::test_tools::tolerance(1e-2));
  for (const auto& r : {coarse, fine, two}) BOOST_TEST(r.balanced);
}

// The two fronts of the strip at 200 cells: the elastic precursor (0 to Y_H) at c = 5875.1 m/s
// and the plastic front (Y_H to the plateau) at c_p = 4708.5 m/s, each within its own width
// (10% to 90% of the jump) of the exact position, with one particle per cell (CTU Euler, Courant
// 0.9) and two along x (Courant 0.5). Measured offsets / widths (m) at t = 4.17e-4 s, after 2.45 m
// and 1.96 m of travel: 1 ppc elastic -0.026 / 0.20, plastic 0.017 / 0.33; 2 ppc elastic -0.038 /
// 0.31, plastic 0.037 / 0.35 (first-order fronts spread like the square root of the distance).
BOOST_AUTO_TEST_CASE(the_fronts_travel_at_the_elastic_and_plastic_wave_speeds) {
  const double nu = 0.3, lambda = E * nu / ((1 + nu) * (1 - 2 * nu)), mu = E / (2 * (1 + nu));
  const double yh = (lambda + 2 * mu) * sigma_y / (2 * mu), c = std::sqrt((lambda + 2 * mu) / rho);
  const double ht = lambda + 2 * mu / 3 + 4 * mu * c_kin / (3 * (3 * mu + c_kin));
  const double cp = std::sqrt(ht / rho), plateau = yh * (1 - cp / c) + rho * cp * v0;
  BOOST_TEST(c == 5875.1, boost::test_tools::tolerance(1e-5));
  BOOST_TEST(cp == 4708.5, boost::test_tools::tolerance(1e-5));
  for (int ppc : {1, 2}) {
    json doc = shipped_strip();
    doc.erase("output");
    for (auto& body : doc["bodies"]) body["particles_per_cell"] = {ppc, 1};
    if (ppc > 1) doc["time"]["courant"] = 0.5;
    const StripResult r = run_strip<PlaneStrainPlastic>(doc);
    const Front elastic = find_front(r.profile, 0.0, yh);
    const Front plastic = find_front(r.profile, yh, plateau);
    BOOST_TEST_MESSAGE(ppc << " ppc: elastic front " << elastic.position - (3 - c * r.time) << " / "
                           << elastic.width << ", plastic " << plastic.position - (3 - cp * r.time)
                           << " / " << plastic.width);
    BOOST_TEST(elastic.width > 0.0);
    BOOST_TEST(plastic.width > 0.0);
    BOOST_TEST(std::abs(elastic.position - (3 - c * r.time)) < elastic.width);
    BOOST_TEST(std::abs(plastic.position - (3 - cp * r.time)) < plastic.width);
    BOOST_TEST(elastic.position < plastic.position);  // the precursor runs ahead
  }
}
