#include "solver/problem_impl.hpp"

#include <dgmpm/exact/elastic_bar.hpp>

#include <algorithm>
#include <climits>
#include <cmath>
#include <fstream>
#include <limits>
#include <numeric>
#include <sstream>

namespace dgmpm {

void set_exact(const scene::Scene& scene, Problem<ElasticBar>& problem) {
  if (!scene.exact) return;
  const auto fail = [&](const std::string& why) {
    return scene::SceneError(scene.source + ": exact: value \"bar\" cannot be used here: " + why);
  };
  const int material = scene.bodies.front().material;
  std::vector<exact::Segment> segments;
  for (const auto& b : scene.bodies) {
    if (b.material != material) throw fail("the exact bar solution needs a single material");
    segments.push_back({b.box_min[0], b.box_max[0], b.stress[0], b.velocity[0]});
  }
  std::sort(segments.begin(), segments.end(),
            [](const auto& a, const auto& b) { return a.x0 < b.x0; });
  for (std::size_t k = 1; k < segments.size(); ++k)
    if (segments[k].x0 != segments[k - 1].x1)
      throw fail("the bodies must form one bar without gaps");
  const double a = segments.front().x0, b = segments.back().x1;
  const auto& m = problem.materials[material];
  const Grid<1>& g = problem.grid;
  std::optional<exact::ElasticBarSolution> solution;
  if (g.periodic[0]) {
    if (a != g.origin[0] || b != g.upper(0))
      throw fail("on a periodic grid the bar must fill the grid");
    solution = exact::ElasticBarSolution::periodic(a, b, m.young, m.density, segments);
  } else {
    // A bar end inside the grid faces void cells: a free surface.
    const auto end = [&](int side, bool at_grid) {
      const auto& segs = problem.boundaries[0][side].segments;
      return at_grid && !segs.empty() ? segs.front().condition : BoundaryCondition<1>{};
    };
    solution = exact::ElasticBarSolution(a, b, m.young, m.density, segments,
                                         end(0, a == g.origin[0]), end(1, b == g.upper(0)));
  }
  problem.exact_impedance = solution->impedance();
  problem.exact = [s = *solution](const Eigen::Matrix<double, 1, 1>& x, double t) {
    return ElasticBar::State(s.stress(x[0], t), s.velocity(x[0], t));
  };
}

void set_exact(const scene::Scene& scene, Problem<ElastoPlasticBar>&) {
  if (scene.exact)
    throw scene::SceneError(scene.source +
                            ": exact: value \"bar\" cannot be used here: the exact bar solution "
                            "is elastic and the scene has plastic materials");
}

void set_exact(const scene::Scene& scene, Problem<UniaxialStrainPlastic>&) {
  if (scene.exact)
    throw scene::SceneError(scene.source +
                            ": exact: value \"bar\" cannot be used here: the exact bar solution "
                            "is in uniaxial stress and the scene in uniaxial strain");
}

void set_exact(const scene::Scene& scene, Problem<PlaneStrainPlastic>&) {
  if (scene.plane_wave || scene.exact)
    throw scene::SceneError(scene.source + ": " + (scene.plane_wave ? "plane_wave" : "exact") +
                            ": cannot be used here: the plane wave is elastic and the scene has "
                            "plastic materials");
}

// The plane wave of the scene, physical state at x and t: v = A sin(k . x - c |k| t) along the
// polarisation; a P wave carries sigma_nn = -Z_p v_n and sigma_tt = lambda / (lambda + 2 mu)
// sigma_nn, an S wave sigma_nt = -Z_s v_t (n = k / |k|).
static PlaneStrain::State plane_wave(const scene::Scene::PlaneWave& w, const Eigen::Vector2d& k,
                                     const PlaneStrain::Material& m, const Eigen::Vector2d& x,
                                     double t) {
  const Eigen::Vector2d n = k.normalized(), tangent(-n[1], n[0]);
  const double c = w.shear ? m.s_speed() : m.p_speed();
  const double v = w.amplitude * std::sin(k.dot(x) - c * k.norm() * t);
  Eigen::Matrix2d sigma;
  Eigen::Vector2d velocity;
  if (w.shear) {
    velocity = v * tangent;
    sigma = -m.s_impedance() * v * (n * tangent.transpose() + tangent * n.transpose());
  } else {
    velocity = v * n;
    const double snn = -m.p_impedance() * v;
    sigma = snn * (n * n.transpose()) +
            m.lambda() / m.p_modulus() * snn * (tangent * tangent.transpose());
  }
  PlaneStrain::State s;
  s << sigma(0, 0), sigma(1, 1), sigma(0, 1), velocity;
  return s;
}

void set_exact(const scene::Scene& scene, Problem<PlaneStrain>& problem) {
  if (!scene.plane_wave) return;
  const auto& w = *scene.plane_wave;
  const Grid<2>& g = problem.grid;
  const Eigen::Vector2d k(2 * M_PI * w.cycles[0] / g.length(0),
                          2 * M_PI * w.cycles[1] / g.length(1));
  const int material = scene.bodies.front().material;
  const PlaneStrain::Material m = problem.materials[material];
  auto& p = problem.particles;
  for (int i = 0; i < p.size(); ++i) {
    const auto& mi = problem.materials[p.material[i]];
    const PlaneStrain::State s = plane_wave(w, k, mi, p.position.col(i), 0.0);
    p.state.col(i) += PlaneStrain::specific(s.head<3>(), s.tail<2>(), mi);
  }
  if (!scene.exact) return;
  const auto fail = [&](const std::string& why) {
    return scene::SceneError(scene.source +
                             ": exact: value \"plane_wave\" cannot be used here: " + why);
  };
  double volume = 0;
  for (std::size_t b = 0; b < scene.bodies.size(); ++b) {
    const auto& body = scene.bodies[b];
    if (body.material != material) throw fail("the plane wave needs a single material");
    for (double x : body.velocity)
      if (x != 0) throw fail("the bodies must be at rest (their velocity adds to the wave's)");
    for (double x : body.stress)
      if (x != 0) throw fail("the bodies must be unstressed (their stress adds to the wave's)");
  }
  for (int i = 0; i < p.size(); ++i) volume += p.volume[i];
  if (std::abs(volume - g.length(0) * g.length(1)) > 1e-9 * volume)
    throw fail("the bodies must fill the grid");
  problem.exact_impedance = w.shear ? m.s_impedance() : m.p_impedance();
  problem.exact = [w, k, m](const Eigen::Vector2d& x, double t) {
    return plane_wave(w, k, m, x, t);
  };
}

// Refuses, before anything is allocated, a scene whose particles and cells would not fit in the
// memory available: bytes per particle and per cell, rounded up from what `dgmpm bench` measures
// (heap bytes per particle with their share of the nodal arrays: about 155 in 1D, 380-800 in 2D
// by flux and integrator).
void check_memory(const scene::Scene& scene) {
  const int dim = scene.dimension;
  double particles = 0, cells = 1;
  for (int k : scene.grid.cells) cells *= k;
  for (std::size_t b = 0; b < scene.bodies.size(); ++b) {
    const auto ranges = scene::box_cells(scene, scene.bodies[b].box_min, scene.bodies[b].box_max);
    double n = static_cast<double>(scene.bodies[b].layout.size());
    for (int a = 0; a < dim; ++a) n *= std::max(0, ranges[a].second - ranges[a].first);
    particles += n;
  }
  const double per_particle = dim == 1 ? 400 : 1200, per_cell = dim == 1 ? 200 : 1000;
  const double needed = particles * per_particle + cells * per_cell;
  double available = 0;  // kB
  std::ifstream meminfo("/proc/meminfo");
  for (std::string key; meminfo >> key;) {
    double value = 0;
    meminfo >> value;
    meminfo.ignore(64, '\n');
    if (key == "MemAvailable:") available = value * 1024;
  }
  if (particles > INT_MAX || (available > 0 && needed > available)) {
    std::ostringstream s;
    s << scene.source << ": bodies: " << particles << " particles on " << cells
      << " cells need about " << needed / 1e9 << " GB";
    if (available > 0) s << ", and this machine has " << available / 1e9 << " GB available";
    s << "; allowed: a scene that fits in memory (at most 2^31 - 1 particles)";
    throw scene::SceneError(s.str());
  }
}

template Problem<ElasticBar> make_problem<ElasticBar>(const scene::Scene&);
template Problem<ElastoPlasticBar> make_problem<ElastoPlasticBar>(const scene::Scene&);
template Problem<PlaneStrain> make_problem<PlaneStrain>(const scene::Scene&);
template Problem<PlaneStrainPlastic> make_problem<PlaneStrainPlastic>(const scene::Scene&);
template Problem<UniaxialStrainPlastic> make_problem<UniaxialStrainPlastic>(const scene::Scene&);
template Problem<FiniteStrainBar<SaintVenantKirchhoff>>
make_problem<FiniteStrainBar<SaintVenantKirchhoff>>(const scene::Scene&);
template Problem<FiniteStrainBar<NeoHookean>>
make_problem<FiniteStrainBar<NeoHookean>>(const scene::Scene&);
template Problem<FiniteStrainPlane<SaintVenantKirchhoff>>
make_problem<FiniteStrainPlane<SaintVenantKirchhoff>>(const scene::Scene&);
template Problem<FiniteStrainPlane<NeoHookean>>
make_problem<FiniteStrainPlane<NeoHookean>>(const scene::Scene&);

}  // namespace dgmpm
