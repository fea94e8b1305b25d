#include "solver/scene_spectrum.hpp"

#include "solver/problem.hpp"

#include <dgmpm/time_integration.hpp>
#include <stability/arpack_spectrum.hpp>
#include <stability/courant_search.hpp>
#include <stability/step_operator.hpp>

#include <algorithm>
#include <iomanip>
#include <nlohmann/json.hpp>
#include <ostream>
#include <variant>

namespace dgmpm {

SceneSpectrumResult analyse_scene_spectrum(const scene::Scene& scene, double tolerance) {
  if (scene.method != scene::Method::dgmpm)
    throw scene::SceneError(scene.source + ": method: value \"" + scene::to_string(scene.method) +
                            "\" has no DGMPM operator to analyse; allowed: \"dgmpm\"");
  BarProblem problem = make_bar_problem(scene);
  using Physics = ElasticBar;

  SceneSpectrumResult result;
  // The homogeneous operator: a traction end acts as a free end, a velocity end as a fixed one;
  // both reflect, as void cells do, so the operator is normal enough for its spectrum to speak.
  Boundaries<1> homogeneous;
  for (int side = 0; side < 2; ++side) {
    const BoundaryKind k = problem.boundaries[0][side].kind;
    homogeneous[0][side].kind = (k == BoundaryKind::fixed || k == BoundaryKind::velocity)
                                    ? BoundaryKind::fixed
                                    : BoundaryKind::free;
  }
  result.boundaries = problem.grid.periodic[0] ? "periodic" : "reflecting";
  result.note = problem.grid.periodic[0]
                    ? "periodic grid: the spectrum is that of the von Neumann analysis on the "
                      "grid's wavenumbers"
                    : "free or fixed ends (traction and velocity ends act as free and fixed in the "
                      "linear part) reflect waves: the spectrum is meaningful";

  Discretisation<Physics> disc;
  disc.build(problem.grid, problem.particles, problem.materials);
  const DGOperator<Physics> op(problem.grid, disc, homogeneous);
  std::variant<ForwardEuler<Physics>, HeunRK2<Physics>> integrator;
  if (scene.time.integrator == scene::Integrator::rk2) integrator.emplace<HeunRK2<Physics>>();

  const double c_max = problem.max_wave_speed();
  const double h = problem.grid.cell_size.minCoeff();
  const int n = Physics::n_comp * problem.particles.size();
  result.unknowns = n;

  const auto radius = [&](double courant) {
    const double dt = courant * h / c_max;
    return std::visit(
        [&](auto& integ) {
          return stability::spectral_radius(
              n, stability::step_operator(op, integ, problem.particles.mass, dt));
        },
        integrator);
  };

  stability::SearchOptions options;
  options.scan_step = 0.02;
  options.max_courant = 2.0;
  options.courant_tolerance = 1e-6;
  options.margin_tolerance = tolerance;
  const auto search = stability::search_admissible_courant(
      [&](double courant) { return radius(courant) - 1.0; }, options);
  result.courant = search.courant;
  result.failing_courant = search.failing_courant;
  result.bounded = search.bounded;
  result.evaluations = search.evaluations;
  if (!scene.time.courant_auto) result.radius_at_scene_courant = radius(scene.time.courant);
  return result;
}

int scene_courant_command(const std::string& path, bool json, std::ostream& out,
                          std::ostream& err) {
  try {
    const scene::Scene scene = scene::load_scene(path);
    const SceneSpectrumResult r = analyse_scene_spectrum(scene);
    if (json) {
      nlohmann::json j{{"scene", path},
                       {"courant", r.courant},
                       {"bounded", r.bounded},
                       {"failing_courant", r.failing_courant},
                       {"time", scene::to_string(scene.time.integrator)},
                       {"criterion", "l2"},
                       {"unknowns", r.unknowns},
                       {"boundaries", r.boundaries},
                       {"note", r.note}};
      if (!scene.time.courant_auto)
        j["spectral_radius_at_scene_courant"] = r.radius_at_scene_courant;
      out << j.dump() << '\n';
      return 0;
    }
    out << std::fixed << std::setprecision(6) << path
        << ": largest Courant number with spectral radius <= 1: " << (r.bounded ? "" : ">= ")
        << r.courant << " (" << scene::to_string(scene.time.integrator) << ", global operator, "
        << r.unknowns << " unknowns, ARPACK)\n"
        << "boundaries: " << r.boundaries << ": " << r.note << '\n';
    if (!scene.time.courant_auto)
      out << "spectral radius at the scene's Courant number " << std::defaultfloat
          << scene.time.courant << ": " << std::setprecision(12) << r.radius_at_scene_courant
          << '\n';
    return 0;
  } catch (const scene::SceneError& e) {
    err << "dgmpm courant: error: " << e.what() << '\n';
    return 2;
  } catch (const std::exception& e) {
    err << "dgmpm courant: error: " << e.what() << '\n';
    return 1;
  }
}

}  // namespace dgmpm
