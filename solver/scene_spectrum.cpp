#include "solver/scene_spectrum.hpp"

#include "solver/frozen_spectrum.hpp"
#include "solver/problem.hpp"
#include "solver/simulation.hpp"

#include <dgmpm/stepper.hpp>
#include <stability/arpack_spectrum.hpp>
#include <stability/courant_search.hpp>
#include <stability/step_operator.hpp>

#include <Eigen/Eigenvalues>

#include <unistd.h>

#include <algorithm>
#include <chrono>
#include <complex>
#include <cstdio>
#include <functional>
#include <iomanip>
#include <map>
#include <nlohmann/json.hpp>
#include <ostream>
#include <stdexcept>
#include <string>
#include <vector>

namespace dgmpm {

namespace {

constexpr int kLargeScene = 2000;  // unknowns

template <class Physics>
SceneSpectrumResult analyse(const scene::Scene& scene, double tolerance) {
  Problem<Physics> problem = make_problem<Physics>(scene);
  SceneSpectrumResult result;
  bool periodic = true;
  for (int a = 0; a < Physics::dim; ++a) periodic = periodic && problem.grid.periodic[a];
  result.boundaries = periodic ? "periodic" : "reflecting";
  result.note = periodic
                    ? "periodic grid: the spectrum is that of the von Neumann analysis on the "
                      "grid's wavenumbers"
                    : "free, fixed or roller sides (traction and velocity sides act as free and "
                      "fixed in the linear part) reflect waves: the spectrum is meaningful";
  const Boundaries<Physics::dim> bc = homogeneous<Physics::dim>(problem.boundaries);
  Stepper<Physics> stepper(problem.grid, bc, stepper_options(scene));
  stepper.rebuild(problem.particles, problem.materials);

  const double c_max = problem.max_wave_speed();
  const double h = problem.grid.cell_size.minCoeff();
  const int n = Physics::n_comp * problem.particles.size();
  result.unknowns = n;
  const auto step = [&](double courant) {
    return stability::step_operator(stepper, problem.particles.mass, courant * h / c_max);
  };
  // Large scenes: ARPACK on ten steps at a time (moduli |lambda|^10 far better separated near the
  // unit circle, where the near-neutral modes of a free body cluster) to a looser accuracy, a
  // coarser scan (0.24: not onto C = 1, where a one-particle-per-cell interior has every mode on
  // the unit circle and ARPACK converges slowest) and a wider final bracket (5e-3), C* to 3 digits:
  // near the limit the growth is too slow for ARPACK to resolve quickly.
  const bool large = n > kLargeScene;
  stability::ArpackOptions arpack;
  if (large) {
    arpack.steps_per_product = 10;
    arpack.basis_size = 60;
    arpack.tolerance = 1e-6;  // of rho^10: rho to about 1e-7
  }
  std::map<double, double> computed;  // the scene's own Courant number is often a scanned one
  std::function<double(double)> radius = [&](double courant) {
    const auto it = computed.find(courant);
    if (it != computed.end()) return it->second;
    return computed[courant] = stability::spectral_radius(n, step(courant), arpack);
  };
  // DCU with Euler and at most one particle per cell: the particle step is I + C L with L
  // independent of C (projection then interpolation is the identity), so the eigenvalues of L,
  // computed once, give rho = max |1 + C lambda| at every C. L comes from lib's Euler step at
  // C = 1 (dense, n columns), and the scene's own stepper is checked against I + C L at another
  // C, so what is analysed is what runs. Otherwise the particle step is no polynomial of one
  // operator (RK2's second stage sees the nodes, not the particles; CTU's operator holds dt;
  // several particles in a cell make projection then interpolation a non-identity): one ARPACK
  // eigenproblem per C.
  std::vector<std::complex<double>> eigenvalues;
  const auto polynomial = [](std::complex<double> z) { return 1.0 + z; };
  bool single_particles = true;
  const auto& disc = stepper.discretisation();
  for (int c = 0; c < disc.num_cells(); ++c)
    single_particles = single_particles && disc.cell_end(c) - disc.cell_begin(c) <= 1;
  bool polynomial_holds = false;
  result.method = "ARPACK per Courant number";
  if ((Physics::dim == 1 || scene.flux == FluxScheme::dcu) &&
      scene.time.integrator == TimeScheme::euler && single_particles) {
    StepperOptions euler_options = stepper_options(scene);
    euler_options.time = TimeScheme::euler;
    Stepper<Physics> euler(problem.grid, bc, euler_options);
    euler.rebuild(problem.particles, problem.materials);
    Eigen::MatrixXd l(n, n);
    Eigen::VectorXd unit = Eigen::VectorXd::Zero(n);
    const auto euler_step = stability::step_operator(euler, problem.particles.mass, h / c_max);
    for (int j = 0; j < n; ++j) {
      unit[j] = 1.0;
      euler_step(unit.data(), l.col(j).data());
      l(j, j) -= 1.0;
      unit[j] = 0.0;
    }
    // The scene's stepper at C = 0.75 against p(0.75 L) on a fixed vector.
    Eigen::VectorXd x = Eigen::VectorXd::LinSpaced(n, -1.0, 1.0).array().sin().matrix(), y(n);
    step(0.75)(x.data(), y.data());
    const Eigen::VectorXd z = x + 0.75 * (l * x);
    polynomial_holds = (z - y).norm() <= 1e-9 * std::max(1.0, x.norm());
    if (polynomial_holds) {
      const Eigen::EigenSolver<Eigen::MatrixXd> solver(l, false);
      for (Eigen::Index k = 0; k < solver.eigenvalues().size(); ++k)
        eigenvalues.push_back(solver.eigenvalues()[k]);
      radius = [&eigenvalues, polynomial](double courant) {
        double rho = 0.0;
        for (const auto& lambda : eigenvalues)
          rho = std::max(rho, std::abs(polynomial(courant * lambda)));
        return rho;
      };
      result.method = "eigenvalues of lib's operator, computed once (dense)";
    }
  }

  stability::SearchOptions options;
  options.scan_step = large ? 0.24 : 0.02;
  options.max_courant = 2.0;
  options.courant_tolerance = large ? 5e-3 : 1e-6;
  options.significant_digits = large ? 3 : 6;
  options.margin_tolerance = tolerance;
  options.bisect = true;  // rho - 1 is 0 up to C*
  // A progress line on a terminal once the search has taken 2 s (ARPACK on a large scene can take
  // minutes).
  const bool terminal = ::isatty(STDERR_FILENO);
  const auto start = std::chrono::steady_clock::now();
  int evaluations = 0;
  bool shown = false;
  const auto search = stability::search_admissible_courant(
      [&](double courant) {
        const double rho = radius(courant);
        const double elapsed =
            std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
        if (terminal && elapsed > 2.0) {
          std::fprintf(
              stderr, "\rscene spectrum: %d Courant numbers tried, C = %.6f: rho = %.9f, %.0f s   ",
              ++evaluations, courant, rho, elapsed);
          shown = true;
        }
        return rho - 1.0;
      },
      options);
  if (shown) std::fprintf(stderr, "\r%90s\r", "");
  result.courant = search.courant;
  result.failing_courant = search.failing_courant;
  result.bounded = search.bounded;
  result.evaluations = search.evaluations;
  if (!scene.time.courant_auto) result.radius_at_scene_courant = radius(scene.time.courant);
  return result;
}

}  // namespace

SceneSpectrumResult analyse_scene_spectrum(const scene::Scene& scene, double tolerance) {
  if (scene.method != scene::Method::dgmpm)
    throw scene::SceneError(scene.source + ": method: value \"" + scene::to_string(scene.method) +
                            "\" has no DGMPM operator to analyse; allowed: \"dgmpm\"");
  for (const auto& m : scene.materials)
    if (m.finite_strain())
      throw scene::SceneError(
          scene.source + ": materials." + m.name + ".model: value \"" + m.model_name() +
          "\" has no linear scene operator to analyse (a finite-strain step is not a linear "
          "map); allowed: small-strain materials (`dgmpm courant` gives a layout's C*, which "
          "the finite-strain automatic step uses)");
  return with_physics(scene, [&](auto physics) {
    return analyse<typename decltype(physics)::type>(scene, tolerance);
  });
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
                       {"method", r.method},
                       {"note", r.note}};
      if (!scene.time.courant_auto)
        j["spectral_radius_at_scene_courant"] = r.radius_at_scene_courant;
      out << j.dump() << '\n';
      return 0;
    }
    out << std::fixed << std::setprecision(6) << path
        << ": largest Courant number with spectral radius <= 1: " << (r.bounded ? "" : ">= ")
        << r.courant << " (" << scene::to_string(scene.time.integrator) << ", global operator, "
        << r.unknowns << " unknowns; " << r.method << ")\n"
        << "boundaries: " << r.boundaries << ": " << r.note << '\n';
    if (!scene.time.courant_auto)
      // Eigenvalues of these non-normal operators are accurate to about 1e-8 (double
      // eigenvalues): more digits would show round-off, e.g. 1.0000000011 for an exact 1.
      out << "spectral radius at the scene's Courant number " << std::defaultfloat
          << scene.time.courant << ": " << std::setprecision(8) << r.radius_at_scene_courant
          << " (to the eigensolver's accuracy, about 1e-8)\n";
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
