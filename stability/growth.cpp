// The growth per step of a one-step map: max over theta of rho(G(theta)) - 1 (docs/method.md,
// "Stability", the growth budget). The L2 margin divides by 1 - cos theta to see the sign of a
// long-wave limit; the budget needs the growth itself, which for a weak instability sits far
// below any scan's spacing: rho - 1 = a theta - b theta^2 off a neutral line peaks at
// a^2 / (4 b), at theta = a / (2 b) (1e-3 to 1e-2 rad for RK2's off-centre particle with the
// paper's pseudo-stiffness). So beside a uniform scan, the lines theta_x = 0 and theta_y = 0 (2D)
// and the origin are approached on a logarithmic scale, and the largest value found is refined.

#include "stability/criteria.hpp"

#include "stability/brent_maximum.hpp"
#include "stability/gsl_guard.hpp"

#include <gsl/gsl_multimin.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <numbers>
#include <vector>

namespace dgmpm::stability {
namespace {

constexpr double kPi = std::numbers::pi;
// Distances from a neutral line or the origin, log-spaced by kNearRatio: 1e-5 to 0.1 rad (a weak
// growth a theta - b theta^2 is within a factor 0.6 of its peak over a factor 4.6 in theta).
constexpr double kNearRatio = 4.641588833612779;  // 10^(2/3)
constexpr std::array<double, 7> kNear = {1e-5, 4.641588833612779e-5, 2.154434690031884e-4,
                                         1e-3, 4.641588833612779e-3, 2.154434690031884e-2,
                                         0.1};

struct Point {
  double value, tx, ty;  // rho - 1 at (tx, ty)
  int kind;              // 0: a point of the scan, 1: off a line toward (ux, uy) from (tx0, ty0)
  double tx0 = 0, ty0 = 0;
  int ux = 0, uy = 0;
  double distance = 0;
};

// rho - 1 of one family at (tx, ty).
struct Surface {
  const FamilySpectrum& spectrum;
  int dim;
  double operator()(double tx, double ty) const {
    return (dim == 1 ? spectrum.radius(tx) : spectrum.radius(tx, ty)) - 1.0;
  }
};

struct Along {
  const Surface* surface;
  const Point* line;
  double at(double d) const {
    return (*surface)(line->tx0 + line->ux * d, line->ty0 + line->uy * d);
  }
};
double negated_surface(const gsl_vector* x, void* surface) {
  return -(*static_cast<const Surface*>(surface))(gsl_vector_get(x, 0), gsl_vector_get(x, 1));
}

// The largest rho - 1 of one family. `uniform`: with the uniform scan of the torus (the L2
// margin's own scan covers it: the margin asks only for the approaches to the lines and the
// origin). Points are evaluated on threads but combined in a fixed order: the result does not
// depend on the number of threads.
L2Growth family_growth(const FamilySpectrum& spectrum, int dim, bool uniform,
                       const TorusSymmetry& symmetry) {
  const Surface f{spectrum, dim};
  std::vector<Point> points;
  if (dim == 1) {
    // Uniform scan of (0, pi] and the origin approached on a log scale.
    for (std::size_t n = 0; n + 1 < kNear.size(); ++n) points.push_back({0, kNear[n], 0.0, 0});
    for (int j = 1; j <= 64; ++j) points.push_back({0, kPi * j / 64, 0.0, 0});
  } else {
    constexpr int k = 16;  // the half torus theta_x in [0, pi], theta_y in (-pi, pi]
    const double h = kPi / k;
    if (uniform)
      for (int i = 0; i <= k; ++i)
        for (int j = -k + 1; j <= k; ++j)
          if (i != 0 || j != 0) points.push_back({0, i * h, j * h, 0});
    // Off the neutral lines and near the origin, on a log scale: toward +x from theta_x = 0,
    // toward +-y from theta_y = 0, along rays from the origin.
    const auto line = [&](double tx0, double ty0, int ux, int uy) {
      for (double d : kNear)
        points.push_back({0, tx0 + ux * d, ty0 + uy * d, 1, tx0, ty0, ux, uy, d});
    };
    // rho is the same at (tx, ty) and (-tx, ty) under the mirror, at (ty, tx) under the swap:
    // the line theta_x = 0 at -t is the one at t, toward -y off theta_y = 0 is toward +y, and
    // the line theta_y = 0 is theta_x = 0's image.
    for (int j = -k + 1; j <= k; ++j)
      if (j > 0 || (j < 0 && !symmetry.mirror)) line(0.0, j * h, 1, 0);
    for (int i = 1; i <= k && !symmetry.swap; ++i) {
      line(i * h, 0.0, 0, 1);
      if (!symmetry.mirror) line(i * h, 0.0, 0, -1);
    }
    for (int q = 0; q < 16; ++q) {
      const double phi = -0.5 * kPi + kPi * q / 16;
      for (std::size_t n = 0; n + 1 < kNear.size(); ++n)
        points.push_back({0, kNear[n] * std::cos(phi), kNear[n] * std::sin(phi), 0});
    }
  }
#pragma omp parallel for schedule(static)
  for (std::size_t p = 0; p < points.size(); ++p) points[p].value = f(points[p].tx, points[p].ty);
  std::size_t b = 0;
  for (std::size_t p = 1; p < points.size(); ++p)
    if (points[p].value > points[b].value) b = p;
  const Point best = points[b];
  double value = best.value, tx = best.tx, ty = best.ty;
  if (dim == 1) {
    // Between the neighbouring points of the scan.
    if (b > 0 && b + 1 < points.size()) {
      auto along = [&](double t) { return f(t, 0.0); };
      brent_maximum(along, points[b - 1].tx, best.tx, points[b + 1].tx, points[b - 1].value,
                    best.value, points[b + 1].value, 1e-3 * best.tx, value, tx);
    }
    return {value, tx, 0.0, 0};
  }
  const double h = kPi / 16;
  if (best.kind == 1) {
    // Along the line's normal, between the neighbouring log-spaced distances.
    const Along along{&f, &best};
    auto g = [&](double d) { return along.at(d); };
    const double lo = best.distance / kNearRatio, hi = std::min(best.distance * kNearRatio, h);
    double where = best.distance;
    brent_maximum(g, lo, best.distance, hi, g(lo), best.value, g(hi), 1e-3 * best.distance, value,
                  where);
    tx = best.tx0 + best.ux * where, ty = best.ty0 + best.uy * where;
  } else {
    GslErrorsAsCodes guard;
    gsl_multimin_function fn{&negated_surface, 2, const_cast<Surface*>(&f)};
    gsl_vector* x = gsl_vector_alloc(2);
    gsl_vector* steps = gsl_vector_alloc(2);
    gsl_vector_set(x, 0, best.tx);
    gsl_vector_set(x, 1, best.ty);
    const double r = std::hypot(best.tx, best.ty);
    gsl_vector_set_all(steps, std::max(r < h ? 0.5 * r : 0.5 * h, 1e-6));
    gsl_multimin_fminimizer* m =
        gsl_multimin_fminimizer_alloc(gsl_multimin_fminimizer_nmsimplex2, 2);
    if (gsl_multimin_fminimizer_set(m, &fn, x, steps) == GSL_SUCCESS) {
      for (int it = 0; it < 100; ++it) {
        if (gsl_multimin_fminimizer_iterate(m) != GSL_SUCCESS) break;
        if (gsl_multimin_test_size(gsl_multimin_fminimizer_size(m), 1e-6) == GSL_SUCCESS) break;
      }
      const double v = -gsl_multimin_fminimizer_minimum(m);
      if (v > value) value = v, tx = gsl_vector_get(m->x, 0), ty = gsl_vector_get(m->x, 1);
    }
    gsl_multimin_fminimizer_free(m);
    gsl_vector_free(steps);
    gsl_vector_free(x);
  }
  return {value, std::abs(tx), ty, 0};
}

}  // namespace

L2Growth L2Criterion::growth(double courant, bool uniform) {
  L2Growth worst;
  for (std::size_t f = 0; f < families_.size(); ++f) {
    families_[f].set_courant(courant);
    L2Growth g =
        family_growth(families_[f], dim_, uniform, dim_ == 2 ? symmetries_[f] : TorusSymmetry{});
    g.family = static_cast<int>(f);
    if (f == 0 || g.value > worst.value) worst = g;
  }
  return worst;
}

}  // namespace dgmpm::stability
