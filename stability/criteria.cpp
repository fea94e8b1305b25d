#include "stability/criteria.hpp"

#include "stability/brent_maximum.hpp"
#include "stability/gsl_guard.hpp"

#include <Eigen/Eigenvalues>
#include <Eigen/SVD>
#include <cmath>
#include <complex>
#include <gsl/gsl_multimin.h>

#include <algorithm>
#include <array>
#include <functional>
#include <limits>
#include <memory>
#include <numbers>
#include <numeric>
#include <vector>

namespace dgmpm::stability {
namespace {

using Complex = std::complex<double>;

double radius_2x2(Complex a, Complex b, Complex c, Complex d) {
  const Complex mean = 0.5 * (a + d), half = 0.5 * (a - d);
  const Complex root = std::sqrt(half * half + b * c);
  // The sign that adds to the mean gives the larger eigenvalue, without cancellation.
  return std::real(std::conj(mean) * root) >= 0.0 ? std::abs(mean + root) : std::abs(mean - root);
}

}  // namespace

FamilySpectrum::FamilySpectrum(const StencilFamily& family)
    : offsets_(family.offsets), offsets_y_(family.offsets_y) {
  const int n = family.size;
  Eigen::MatrixXd stacked(n, 0);
  for (const auto& by_power : family.coefficients)
    for (const auto& c : by_power) {
      stacked.conservativeResize(Eigen::NoChange, stacked.cols() + n);
      stacked.rightCols(n) = c;
    }
  Eigen::JacobiSVD<Eigen::MatrixXd> svd(stacked, Eigen::ComputeThinU);
  const auto& sigma = svd.singularValues();
  rank_ = 0;
  while (rank_ < sigma.size() && sigma[rank_] > 1e-12 * sigma[0]) ++rank_;
  const Eigen::MatrixXd u = svd.matrixU().leftCols(rank_);
  for (const auto& by_power : family.coefficients) {
    reduced_.emplace_back();
    for (const auto& c : by_power) reduced_.back().push_back(u.transpose() * c * u);
  }
  at_courant_.resize(offsets_.size());
  set_courant(0.0);
}

void FamilySpectrum::set_courant(double courant) {
  for (std::size_t i = 0; i < offsets_.size(); ++i) {
    const auto& c = reduced_[i];
    at_courant_[i] = c.back();
    for (int k = static_cast<int>(c.size()) - 2; k >= 0; --k)
      at_courant_[i] = at_courant_[i] * courant + c[k];
  }
}

double FamilySpectrum::radius(double theta) const {
  return radius(std::polar(1.0, -theta));
}

double FamilySpectrum::radius(Complex phase) const {
  if (rank_ == 0) return 0.0;
  // e^{-i d theta} for the (small) offsets d, by products rather than trigonometric calls.
  const auto power = [phase](int d) {
    Complex p = 1.0;
    const Complex f = d >= 0 ? phase : std::conj(phase);
    for (int k = 0; k < std::abs(d); ++k) p *= f;
    return p;
  };
  if (rank_ <= 2) {
    Complex z[2][2] = {};
    for (std::size_t i = 0; i < offsets_.size(); ++i) {
      const Complex p = power(offsets_[i]);
      for (int r = 0; r < rank_; ++r)
        for (int s = 0; s < rank_; ++s) z[r][s] += p * at_courant_[i](r, s);
    }
    return rank_ == 1 ? std::abs(z[0][0]) : radius_2x2(z[0][0], z[0][1], z[1][0], z[1][1]);
  }
  Eigen::MatrixXcd g = Eigen::MatrixXcd::Zero(rank_, rank_);
  for (std::size_t i = 0; i < offsets_.size(); ++i)
    g += power(offsets_[i]) * at_courant_[i].cast<Complex>();
  return Eigen::ComplexEigenSolver<Eigen::MatrixXcd>(g, false).eigenvalues().cwiseAbs().maxCoeff();
}

double FamilySpectrum::radius(double theta_x, double theta_y) const {
  return radius(std::polar(1.0, -theta_x), std::polar(1.0, -theta_y));
}

double FamilySpectrum::radius(Complex phase_x, Complex phase_y) const {
  if (rank_ == 0) return 0.0;
  const auto power = [](Complex phase, int d) {
    Complex p = 1.0;
    const Complex f = d >= 0 ? phase : std::conj(phase);
    for (int k = 0; k < std::abs(d); ++k) p *= f;
    return p;
  };
  Eigen::MatrixXcd g = Eigen::MatrixXcd::Zero(rank_, rank_);
  for (std::size_t i = 0; i < offsets_.size(); ++i)
    g += (power(phase_x, offsets_[i]) * power(phase_y, offsets_y_[i])) *
         at_courant_[i].cast<Complex>();
  if (rank_ == 1) return std::abs(g(0, 0));
  if (rank_ == 2) return radius_2x2(g(0, 0), g(0, 1), g(1, 0), g(1, 1));
  return Eigen::ComplexEigenSolver<Eigen::MatrixXcd>(g, false).eigenvalues().cwiseAbs().maxCoeff();
}

namespace {

// Theta scan of the L2 margin: kThetaPoints uniform points in (0, pi], then Brent refinement of
// every local maximum. Below 2 kSmallTheta, (rho - 1) / (1 - cos theta) loses digits to
// cancellation (rho - 1 ~ theta^2), so it is replaced by its even quadratic model through the
// Richardson limit at 0 (from kSmallTheta and 2 kSmallTheta, error O(kSmallTheta^4)) and the value
// at 2 kSmallTheta. Round-off of the margin: ~1e-16 / (1 - cos 0.01) ~ 1e-11, hence the 1e-9
// tolerance.
constexpr int kThetaPoints = 32;
constexpr double kSmallTheta = 0.01;
static_assert(std::numbers::pi / kThetaPoints > 2.0 * kSmallTheta);

struct ThetaProfile {
  const FamilySpectrum& spectrum;
  double limit_at_zero = 0.0, at_two_small = 0.0;

  double direct(double theta) const {
    const double s = std::sin(0.5 * theta);
    return (spectrum.radius(theta) - 1.0) / (2.0 * s * s);
  }
  void prepare() {
    at_two_small = direct(2.0 * kSmallTheta);
    limit_at_zero = (4.0 * direct(kSmallTheta) - at_two_small) / 3.0;
  }
  double operator()(double theta) const {
    if (theta >= 2.0 * kSmallTheta) return direct(theta);
    const double t = theta / (2.0 * kSmallTheta);
    return limit_at_zero + (at_two_small - limit_at_zero) * t * t;
  }
};

// The scan's wavenumbers, their phases e^{-i theta} and 1 - cos theta, computed once.
struct ThetaGrid {
  double theta[kThetaPoints + 1], one_minus_cos[kThetaPoints + 1];
  Complex phase[kThetaPoints + 1];
  ThetaGrid() {
    for (int j = 0; j <= kThetaPoints; ++j) {
      theta[j] = std::numbers::pi * j / kThetaPoints;
      const double s = std::sin(0.5 * theta[j]);
      one_minus_cos[j] = 2.0 * s * s;
      phase[j] = std::polar(1.0, -theta[j]);
    }
  }
};

L2Margin family_margin(FamilySpectrum& spectrum, double courant) {
  static const ThetaGrid grid;
  spectrum.set_courant(courant);
  ThetaProfile profile{spectrum};
  profile.prepare();
  const double* thetas = grid.theta;
  double values[kThetaPoints + 1];
  values[0] = profile.limit_at_zero;
  for (int j = 1; j <= kThetaPoints; ++j)  // the grid starts above 2 kSmallTheta
    values[j] = (spectrum.radius(grid.phase[j]) - 1.0) / grid.one_minus_cos[j];
  double best = values[0], best_theta = 0.0;
  for (int j = 1; j <= kThetaPoints; ++j)
    if (values[j] > best) best = values[j], best_theta = thetas[j];
  // theta = 0 and pi are stationary (rho is even and 2 pi-periodic): only interior maxima move.
  for (int j = 1; j < kThetaPoints; ++j)
    if (values[j] >= values[j - 1] && values[j] >= values[j + 1])
      brent_maximum(profile, thetas[j - 1], thetas[j], thetas[j + 1], values[j - 1], values[j],
                    values[j + 1], 1e-7, best, best_theta);
  return {best, best_theta, 0};
}

// --- 2D ---------------------------------------------------------------------------------------
// The symbol is even (rho(-theta) = rho(theta)), so the half torus theta_x in [0, pi],
// theta_y in (-pi, pi] is scanned: K + 1 by 2 K points, spacing pi / K. The margin there is
// (rho - 1) / s, s = 2 - cos theta_x - cos theta_y (|theta|^2 / 2 near 0). Below |theta| =
// 2 kSmall2D the margin loses digits (rho - 1 ~ |theta|^2, eigenvalues of nearly coincident
// modes carry errors near 1e-12), so along each of R directions it is replaced by its
// quadratic model through the Richardson limit at 0 (from kSmall2D and 2 kSmall2D) and the value
// at 2 kSmall2D, as in 1D. The largest local maxima of the scan are refined by a simplex.
//
// Elasticity has a zero-speed mode along each axis (sigma_yy for waves along x, sigma_xx along
// y), so rho = 1 on the whole lines theta_x = 0 and theta_y = 0, not only at the origin. Off
// those lines rho - 1 may grow linearly, a theta - b theta^2: a weak instability (at most
// a^2 / (4 b) per step) confined to theta ~ a / (2 b), far below the scan's spacing (one
// particle off the centre on both axes under RK2: a ~ 0.016 C^3 per radian). Where rho = 1 on a
// line, its one-sided slope off the line, a, is a margin of its own (per radian, from rho at
// kLine2D, 2 kLine2D and 3 kLine2D). Off a stable line, rho - 1 = -b theta^2 + c theta^3 + ...,
// and the three-point slope reads 2 c kLine2D^2, the four-point one 6 d kLine2D^3: near 1e-7 for
// some stable layouts, the size of the tolerance. The margin is the four-point slope less the
// two estimates' difference: a real slope (1e-3 per radian for RK2's off-centre particle) passes
// through it unchanged, a truncation error does not read as one.
//
// The full sweep (kFine) decides; the search scans C with a coarse one (kCoarse) and refines
// with a few probes (admissible_courant.cpp).
struct TorusResolution {
  int scan;             // K
  int rays;             // R, even
  bool slopes;          // the neutral lines' slopes
  std::size_t refined;  // local maxima refined by a simplex
};
constexpr TorusResolution kFine{16, 16, true, 4};
constexpr TorusResolution kCoarse{2, 4, false, 0};
constexpr double kSmall2D = 0.05;
constexpr double kLine2D = 1e-3;
constexpr double kNone = -std::numeric_limits<double>::infinity();

struct TorusProfile {
  const FamilySpectrum& spectrum;

  static double s_of(double tx, double ty) {
    const double a = std::sin(0.5 * tx), b = std::sin(0.5 * ty);
    return 2.0 * (a * a + b * b);
  }
  double direct(double tx, double ty) const {
    return (spectrum.radius(tx, ty) - 1.0) / s_of(tx, ty);
  }
  // Richardson limit at 0 along the direction phi, and the value at 2 kSmall2D on it.
  std::pair<double, double> ray(double phi) const {
    const double c = std::cos(phi), s = std::sin(phi);
    const double near = direct(kSmall2D * c, kSmall2D * s);
    const double far = direct(2 * kSmall2D * c, 2 * kSmall2D * s);
    return {(4.0 * near - far) / 3.0, far};
  }
  double operator()(double tx, double ty) const {
    const double r = std::hypot(tx, ty);
    if (r >= 2.0 * kSmall2D) return direct(tx, ty);
    const auto [limit, far] = ray(std::atan2(ty, tx));
    const double t = r / (2.0 * kSmall2D);
    return limit + (far - limit) * t * t;
  }
  // Slope of rho off a neutral line at (tx, ty), toward (ux, uy) (a unit axis vector); f0 =
  // rho - 1 on the line. None where rho < 1 there.
  double line_slope(double tx, double ty, int ux, int uy, double f0) const {
    if (f0 < -1e-10) return kNone;
    const double dx = ux * kLine2D, dy = uy * kLine2D;
    const double f1 = spectrum.radius(tx + dx, ty + dy) - 1.0;
    const double f2 = spectrum.radius(tx + 2 * dx, ty + 2 * dy) - 1.0;
    const double f3 = spectrum.radius(tx + 3 * dx, ty + 3 * dy) - 1.0;
    const double three = (4.0 * f1 - f2 - 3.0 * f0) / (2.0 * kLine2D);
    const double four = (18.0 * f1 - 9.0 * f2 + 2.0 * f3 - 11.0 * f0) / (6.0 * kLine2D);
    return four - std::abs(four - three);
  }
  double line_slope(double tx, double ty, int ux, int uy) const {
    return line_slope(tx, ty, ux, uy, spectrum.radius(tx, ty) - 1.0);
  }
  double probe(const L2Margin& p) const {
    switch (p.kind) {
      case L2Probe::ray:
        return ray(p.phi).first;
      case L2Probe::line:
        return line_slope(p.theta - p.line_x * kLine2D, p.theta_y - p.line_y * kLine2D, p.line_x,
                          p.line_y);
      case L2Probe::point:
        break;
    }
    return (*this)(p.theta, p.theta_y);
  }
};

int wrap(int a, int k) {  // into (-k, k]
  return ((a + k - 1) % (2 * k) + 2 * k) % (2 * k) - (k - 1);
}

// The scan's points and rays, and which of them a symmetry of the symbol makes equal: rho is
// evaluated once per class, at its representative.
struct TorusGrid {
  TorusResolution resolution;
  TorusSymmetry symmetry;
  int nx, ny;
  double h;
  std::vector<int> representative, unique;  // per point (i * ny + j); the representatives
  std::vector<int> ray_representative, unique_rays;

  TorusGrid(TorusResolution r, TorusSymmetry symmetry)
      : resolution(r), symmetry(symmetry), nx(r.scan + 1), ny(2 * r.scan),
        h(std::numbers::pi / r.scan) {
    const int k = r.scan;
    // Point (a, b) h (any integers) -> index in the half torus, by the symbol's evenness.
    const auto index = [k, this](int a, int b) {
      a = wrap(a, k), b = wrap(b, k);
      if (a < 0) a = -a, b = wrap(-b, k);
      return a * ny + b + k - 1;
    };
    const auto orbit_min = [&](int a, int b) {
      std::vector<std::pair<int, int>> orbit{{a, b}};
      for (std::size_t q = 0; q < orbit.size(); ++q) {
        const auto [x, y] = orbit[q];
        std::vector<std::pair<int, int>> images{{-x, -y}};
        if (symmetry.mirror) images.push_back({-x, y});
        if (symmetry.swap) images.push_back({y, x});
        for (auto [u, v] : images) {
          u = wrap(u, k), v = wrap(v, k);
          if (std::find(orbit.begin(), orbit.end(), std::pair{u, v}) == orbit.end())
            orbit.push_back({u, v});
        }
      }
      int best = index(a, b);
      for (const auto& [u, v] : orbit) best = std::min(best, index(u, v));
      return best;
    };
    representative.resize(static_cast<std::size_t>(nx * ny));
    for (int i = 0; i < nx; ++i)
      for (int j = 0; j < ny; ++j) {
        const int rep = orbit_min(i, j - k + 1);
        representative[static_cast<std::size_t>(i * ny + j)] = rep;
        if (rep == i * ny + j) unique.push_back(rep);
      }
    // Rays: direction m pi / R, m = ray - R / 2 in [-R/2, R/2) (the half plane theta_x >= 0).
    const int rays = r.rays;
    const auto ray_index = [rays](int m) {
      m = ((m + rays / 2) % (2 * rays) + 2 * rays) % (2 * rays) - rays / 2;  // [-R/2, 3R/2)
      if (m >= rays / 2) m -= rays;                                          // the opposite one
      return m + rays / 2;
    };
    ray_representative.resize(static_cast<std::size_t>(rays));
    for (int q = 0; q < rays; ++q) {
      std::vector<int> orbit{q - rays / 2};
      for (std::size_t o = 0; o < orbit.size(); ++o) {
        std::vector<int> images;
        if (symmetry.mirror) images.push_back(rays - orbit[o]);
        if (symmetry.swap) images.push_back(rays / 2 - orbit[o]);
        for (int m : images)
          if (std::none_of(orbit.begin(), orbit.end(),
                           [&](int x) { return ray_index(x) == ray_index(m); }))
            orbit.push_back(m);
      }
      int best = q;
      for (int m : orbit) best = std::min(best, ray_index(m));
      ray_representative[static_cast<std::size_t>(q)] = best;
      if (best == q) unique_rays.push_back(q);
    }
  }
  double theta_x(int i) const { return i * h; }
  double theta_y(int j) const { return (j - resolution.scan + 1) * h; }
  double phi(int ray) const {
    return -0.5 * std::numbers::pi + std::numbers::pi * ray / resolution.rays;
  }
};

double negated_torus(const gsl_vector* x, void* profile) {
  return -(*static_cast<const TorusProfile*>(profile))(gsl_vector_get(x, 0), gsl_vector_get(x, 1));
}

void refine_torus_maximum(const TorusProfile& profile, double tx, double ty, double step,
                          L2Margin& best) {
  gsl_multimin_function f{&negated_torus, 2, const_cast<TorusProfile*>(&profile)};
  gsl_vector* x = gsl_vector_alloc(2);
  gsl_vector* steps = gsl_vector_alloc(2);
  gsl_vector_set(x, 0, tx);
  gsl_vector_set(x, 1, ty);
  gsl_vector_set_all(steps, 0.5 * step);
  gsl_multimin_fminimizer* m = gsl_multimin_fminimizer_alloc(gsl_multimin_fminimizer_nmsimplex2, 2);
  if (gsl_multimin_fminimizer_set(m, &f, x, steps) == GSL_SUCCESS) {
    for (int it = 0; it < 80; ++it) {
      if (gsl_multimin_fminimizer_iterate(m) != GSL_SUCCESS) break;
      if (gsl_multimin_test_size(gsl_multimin_fminimizer_size(m), 1e-4) == GSL_SUCCESS) break;
    }
    const double value = -gsl_multimin_fminimizer_minimum(m);
    if (value > best.value) {
      best.value = value;
      best.theta = gsl_vector_get(m->x, 0);
      best.theta_y = gsl_vector_get(m->x, 1);
      best.kind = L2Probe::point;
    }
  }
  gsl_multimin_fminimizer_free(m);
  gsl_vector_free(steps);
  gsl_vector_free(x);
}

// stop_above: the caller only needs to know whether the margin exceeds it, so the probe that
// exceeded it last time (`hint`) is tried first, and refinement is skipped once the scan exceeds
// it. Points are evaluated in parallel but combined in a fixed order: the result does not depend on
// the number of threads.
L2Margin torus_margin(const FamilySpectrum& spectrum, const TorusGrid& grid, double stop_above,
                      L2Margin& hint) {
  const TorusProfile profile{spectrum};
  if (stop_above < std::numeric_limits<double>::infinity() && hint.value > kNone) {
    L2Margin m = hint;
    m.value = profile.probe(hint);
    if (m.value > stop_above) return m;
  }
  L2Margin best{kNone, 0.0, 0.0, 0};
  // Long waves: the limit at 0 along each direction of the half plane.
  const auto& rays = grid.unique_rays;
  std::vector<double> ray_limits(static_cast<std::size_t>(grid.resolution.rays));
#pragma omp parallel for schedule(static)
  for (std::size_t q = 0; q < rays.size(); ++q)
    ray_limits[static_cast<std::size_t>(rays[q])] = profile.ray(grid.phi(rays[q])).first;
  for (int q = 0; q < grid.resolution.rays; ++q) {
    const double v = ray_limits[static_cast<std::size_t>(grid.ray_representative[q])];
    if (v > best.value) best = {v, 0.0, 0.0, 0, L2Probe::ray, grid.phi(q)};
  }
  const int k = grid.resolution.scan, nx = grid.nx, ny = grid.ny;
  std::vector<double> values(static_cast<std::size_t>(nx * ny));
  const auto& unique = grid.unique;
#pragma omp parallel for schedule(dynamic)
  for (std::size_t q = 0; q < unique.size(); ++q) {
    const int i = unique[q] / ny, j = unique[q] % ny;
    const double tx = grid.theta_x(i), ty = grid.theta_y(j);
    values[static_cast<std::size_t>(unique[q])] =
        std::hypot(tx, ty) < 2.0 * kSmall2D ? profile(tx, ty) : profile.direct(tx, ty);
  }
  for (std::size_t p = 0; p < values.size(); ++p)
    values[p] = values[static_cast<std::size_t>(grid.representative[p])];
  const auto at = [&](int i, int j) -> double {
    return values[static_cast<std::size_t>(i * ny + ((j % ny) + ny) % ny)];
  };
  // Local maxima (8 neighbours; theta_y wraps, theta_x is mirrored at 0 and pi), largest first.
  std::vector<std::pair<double, std::pair<int, int>>> maxima;
  for (int i = 0; i < nx; ++i)
    for (int j = 0; j < ny; ++j) {
      const double v = at(i, j);
      bool is_max = true;
      for (int di = -1; di <= 1 && is_max; ++di)
        for (int dj = -1; dj <= 1; ++dj) {
          if (!di && !dj) continue;
          int ii = i + di, jj = j + dj;
          if (ii < 0 || ii >= nx) {  // mirror: rho(-tx, -ty) = rho(tx, ty), tx = pi + h ~ -(pi - h)
            ii = ii < 0 ? -ii : 2 * k - ii;
            jj = 2 * (k - 1) - jj;
          }
          if (at(ii, jj) > v) {
            is_max = false;
            break;
          }
        }
      if (is_max) maxima.push_back({v, {i, j}});
      if (v > best.value) best = {v, grid.theta_x(i), grid.theta_y(j), 0};
    }
  const auto finish = [&] {
    best.theta = std::abs(best.theta);
    if (best.value > stop_above) hint = best;
    return best;
  };
  if (best.value > stop_above) return finish();
  std::sort(maxima.begin(), maxima.end(),
            [](const auto& a, const auto& b) { return a.first > b.first; });
  // Refinement sharpens the largest maxima (one per class of symmetric points), but not the
  // neutral points of the axis lines (rho = 1 there: the slope checks below decide). (Skipping
  // maxima below a threshold is unsafe: a peak between grid points can lie above zero while the
  // scan's values are below -1e-3.)
  std::vector<std::pair<int, int>> starts;
  std::vector<int> started;
  for (std::size_t q = 0; q < maxima.size() && starts.size() < grid.resolution.refined; ++q) {
    const auto [i, j] = maxima[q].second;
    const bool on_axis_line = i == 0 || j == k - 1;
    const bool neutral = on_axis_line && std::abs(maxima[q].first) < 1e-9;  // rho = 1 there
    const int rep = grid.representative[static_cast<std::size_t>(i * ny + j)];
    if (neutral || std::find(started.begin(), started.end(), rep) != started.end()) continue;
    started.push_back(rep);
    starts.push_back({i, j});
  }
  std::vector<L2Margin> refined(starts.size(), best);
  {
    GslErrorsAsCodes guard;  // set once: the handler is global
#pragma omp parallel for schedule(dynamic)
    for (std::size_t q = 0; q < starts.size(); ++q)
      refine_torus_maximum(profile, grid.theta_x(starts[q].first), grid.theta_y(starts[q].second),
                           grid.h, refined[q]);
  }
  for (const auto& r : refined)
    if (r.value > best.value) best = r;
  if (!grid.resolution.slopes) return finish();
  // The neutral lines: slope of rho off theta_x = 0 (toward theta_x > 0) and off theta_y = 0
  // (both ways, theta_x in [0, pi] only), where rho = 1 on the line (rho there is the scan's).
  // A mirror symmetry makes the slopes at theta_y = -t those at t, and the two ways off
  // theta_y = 0 equal; the swap makes the line theta_y = 0 the other line.
  const TorusSymmetry& symmetry = grid.symmetry;
  std::vector<std::array<double, 3>> slopes(static_cast<std::size_t>(ny), {kNone, kNone, kNone});
#pragma omp parallel for schedule(dynamic)
  for (int j = 0; j < ny; ++j) {
    const double t = grid.theta_y(j);
    if (std::abs(t) < 2.0 * kSmall2D) continue;  // the origin is the rays' business
    const auto rho_minus_one = [&](int i, int jj) {
      return at(i, jj) * TorusProfile::s_of(grid.theta_x(i), grid.theta_y(jj));
    };
    auto& s = slopes[static_cast<std::size_t>(j)];
    if (t > 0 || !symmetry.mirror) s[0] = profile.line_slope(0.0, t, 1, 0, rho_minus_one(0, j));
    if (t > 0 && !symmetry.swap) {
      const int i = j - k + 1;  // theta_x = t on the grid
      s[1] = profile.line_slope(t, 0.0, 0, 1, rho_minus_one(i, k - 1));
      if (!symmetry.mirror) s[2] = profile.line_slope(t, 0.0, 0, -1, rho_minus_one(i, k - 1));
    }
  }
  for (int j = 0; j < ny; ++j) {
    const double t = grid.theta_y(j);
    const auto& s = slopes[static_cast<std::size_t>(j)];
    if (s[0] > best.value) best = {s[0], kLine2D, t, 0, L2Probe::line, 0.0, 1, 0};
    if (s[1] > best.value) best = {s[1], t, kLine2D, 0, L2Probe::line, 0.0, 0, 1};
    if (s[2] > best.value) best = {s[2], t, -kLine2D, 0, L2Probe::line, 0.0, 0, -1};
  }
  return finish();
}

// Whether the signed permutation of unknowns made of `particles` (particle p -> particles[p]) and
// a signed involution of the components maps every B_{d,k} to B_{offset_map(d),k}: then
// G(sigma theta) = S G(theta) S^T, and rho is the same at theta and sigma theta.
template <class OffsetMap>
bool maps_blocks(const StencilFamily& f, int n, const std::vector<int>& particles,
                 OffsetMap offset_map, double tolerance) {
  const int ncomp = f.size / n;
  std::vector<int> target(static_cast<std::size_t>(f.offsets.size()), -1);
  for (std::size_t o = 0; o < f.offsets.size(); ++o) {
    const auto [dx, dy] = offset_map(f.offsets[o], f.offsets_y[o]);
    for (std::size_t q = 0; q < f.offsets.size(); ++q)
      if (f.offsets[q] == dx && f.offsets_y[q] == dy) target[o] = static_cast<int>(q);
    if (target[o] < 0) return false;
  }
  std::vector<int> perm(static_cast<std::size_t>(ncomp));
  std::iota(perm.begin(), perm.end(), 0);
  do {
    bool involution = true;
    for (int c = 0; c < ncomp; ++c) involution = involution && perm[perm[c]] == c;
    if (!involution) continue;
    for (int signs = 0; signs < (1 << ncomp); ++signs) {
      const auto unknown = [&](int u) { return perm[u / n] * n + particles[u % n]; };
      const auto sign = [&](int u) { return (signs >> (u / n)) & 1 ? -1.0 : 1.0; };
      bool all = true;
      for (std::size_t o = 0; o < f.offsets.size() && all; ++o)
        for (std::size_t p = 0; p < f.coefficients[o].size() && all; ++p) {
          const auto& from = f.coefficients[o][p];
          const auto& to = f.coefficients[static_cast<std::size_t>(target[o])][p];
          for (int r = 0; r < f.size && all; ++r)
            for (int s = 0; s < f.size && all; ++s)
              all = std::abs(to(unknown(r), unknown(s)) - sign(r) * sign(s) * from(r, s)) <=
                    tolerance;
        }
      if (all) return true;
    }
  } while (std::next_permutation(perm.begin(), perm.end()));
  return false;
}

// The particle that `image` (a map of [0, 1]^2) sends each particle to, or empty.
template <class Image>
std::vector<int> particle_map(const CellLayout& layout, Image image) {
  std::vector<int> to;
  for (int p = 0; p < layout.size(); ++p) {
    const auto [x, y] = image(layout.position(p, 0), layout.position(p, 1));
    int found = -1;
    for (int q = 0; q < layout.size() && found < 0; ++q)
      if (std::abs(layout.position(q, 0) - x) <= 1e-12 &&
          std::abs(layout.position(q, 1) - y) <= 1e-12 &&
          std::abs(layout.weight(q) - layout.weight(p)) <= 1e-12 * layout.weight(p))
        found = q;
    if (found < 0) return {};
    to.push_back(found);
  }
  return to;
}

}  // namespace

TorusSymmetry detect_torus_symmetry(const StencilFamily& family, const CellLayout& layout,
                                    double round_off) {
  TorusSymmetry symmetry;
  if (layout.dim != 2 || family.size % layout.size() != 0) return symmetry;
  double scale = 0.0;
  for (const auto& by_power : family.coefficients)
    for (const auto& c : by_power) scale = std::max(scale, c.cwiseAbs().maxCoeff());
  const double tolerance = std::max(1e-13, 100.0 * round_off) * scale;
  const int n = layout.size();
  const auto check = [&](auto image, auto offset_map) {
    const std::vector<int> particles = particle_map(layout, image);
    return !particles.empty() && maps_blocks(family, n, particles, offset_map, tolerance);
  };
  const auto mirror_x = [](double x, double y) { return std::pair{1.0 - x, y}; };
  const auto mirror_y = [](double x, double y) { return std::pair{x, 1.0 - y}; };
  const auto swap = [](double x, double y) { return std::pair{y, x}; };
  symmetry.mirror = check(mirror_x,
                          [](int dx, int dy) {
                            return std::pair{-dx, dy};
                          }) ||
                    check(mirror_y, [](int dx, int dy) {
                      return std::pair{dx, -dy};
                    });
  symmetry.swap = check(swap, [](int dx, int dy) { return std::pair{dy, dx}; });
  return symmetry;
}

// Long waves between the margin's rays. The limit at 0 along a direction can peak in a cone
// narrower than the rays' spacing (pi / 16): one particle off the centre on both axes, under
// RK2, has a cone 0.059 rad off an axis, 0.01 rad wide where it crosses 0, and its limit
// there rises from -3.5e-6 to +6.3e-6 within 1e-5 of C*. So the check samples kCheckRays directions
// of the half plane and refines the largest interior local maxima by Brent. The axis directions,
// along the neutral lines, are local maxima of value 0 (rho = 1 there): a cone closer to an axis
// than one spacing (0.025 rad) is not resolved.
constexpr int kCheckRays = 128;
constexpr std::size_t kCheckRaysRefined = 4;

L2Margin long_wave_maximum(const TorusProfile& profile) {
  std::vector<double> limits(kCheckRays);
  const auto phi = [](int q) {
    return -0.5 * std::numbers::pi + std::numbers::pi * q / kCheckRays;
  };
#pragma omp parallel for schedule(static)
  for (int q = 0; q < kCheckRays; ++q)
    limits[static_cast<std::size_t>(q)] = profile.ray(phi(q)).first;
  const auto at = [&](int q) {  // the half plane's directions wrap: -pi / 2 is pi / 2
    return limits[static_cast<std::size_t>((q + kCheckRays) % kCheckRays)];
  };
  L2Margin best{kNone, 0.0, 0.0, 0, L2Probe::ray, 0.0};
  std::vector<std::pair<double, int>> maxima;
  for (int q = 0; q < kCheckRays; ++q) {
    if (at(q) > best.value) best.value = at(q), best.phi = phi(q);
    const bool axis = q == 0 || q == kCheckRays / 2;
    if (!axis && at(q) > at(q - 1) && at(q) > at(q + 1)) maxima.push_back({at(q), q});
  }
  std::sort(maxima.begin(), maxima.end(), std::greater<>());
  if (maxima.size() > kCheckRaysRefined) maxima.resize(kCheckRaysRefined);
  const auto limit = [&](double p) { return profile.ray(p).first; };
  for (const auto& [value, q] : maxima)
    brent_maximum(limit, phi(q - 1), phi(q), phi(q + 1), at(q - 1), value, at(q + 1), 1e-7,
                  best.value, best.phi);
  return best;
}

struct L2Criterion::Torus {
  TorusGrid fine, coarse;
};

L2Criterion::L2Criterion(const OneStepMap& map) : dim_(map.setting.dim) {
  for (const auto& f : map.families) {
    families_.emplace_back(f);
    if (dim_ == 2) {
      const TorusSymmetry s = detect_torus_symmetry(f, map.layout, map.round_off);
      symmetries_.push_back(s);
      tori_.push_back(std::make_shared<Torus>(Torus{TorusGrid(kFine, s), TorusGrid(kCoarse, s)}));
    }
  }
  hints_.resize(families_.size());
  for (auto& h : hints_) h.value = kNone;
}

L2Margin L2Criterion::sweep(double courant, double stop_above, bool coarse) {
  L2Margin worst;
  for (std::size_t f = 0; f < families_.size(); ++f) {
    families_[f].set_courant(courant);
    L2Margin m = dim_ == 1 ? family_margin(families_[f], courant)
                           : torus_margin(families_[f], coarse ? tori_[f]->coarse : tori_[f]->fine,
                                          stop_above, hints_[f]);
    m.family = static_cast<int>(f);
    if (f == 0 || m.value > worst.value) worst = m;
  }
  return worst;
}

L2Margin L2Criterion::margin(double courant, double stop_above) {
  return sweep(courant, stop_above, false);
}

L2Margin L2Criterion::checked_margin(double courant, double stop_above) {
  L2Margin m = margin(courant, stop_above);
  if (dim_ == 1 || m.value > stop_above) return m;
  // The scan and the slopes can miss a weak growth between their points, off a line that is not
  // exactly neutral (rho - 1 = -1e-9 on it, 3e-4 at 0.035 rad from it): the growth search
  // approaches the lines on a log scale, and the margin where it finds its maximum counts too.
  const L2Growth g = growth(courant, false);
  L2Margin at{0.0, g.theta, g.theta_y, g.family};
  at.value = probe_margin(courant, at);
  if (at.value > m.value) m = at;
  if (m.value > stop_above) return m;
  // And the long waves between the margin's rays (long_wave_maximum).
  for (std::size_t f = 0; f < families_.size(); ++f) {
    families_[f].set_courant(courant);
    L2Margin ray = long_wave_maximum(TorusProfile{families_[f]});
    ray.family = static_cast<int>(f);
    if (ray.value > m.value) m = ray;
  }
  return m;
}

L2Margin L2Criterion::coarse_margin(double courant, double stop_above) {
  return sweep(courant, stop_above, dim_ == 2);
}

double L2Criterion::probe_margin(double courant, const L2Margin& probe) {
  if (dim_ == 1) return margin(courant).value;
  auto& spectrum = families_[static_cast<std::size_t>(probe.family)];
  spectrum.set_courant(courant);
  return TorusProfile{spectrum}.probe(probe);
}

L2Margin L2Criterion::sharpen(double courant, const L2Margin& probe) {
  L2Margin best = probe;
  if (dim_ == 1 || probe.kind != L2Probe::point) {
    best.value = probe_margin(courant, probe);
    return best;
  }
  auto& spectrum = families_[static_cast<std::size_t>(probe.family)];
  spectrum.set_courant(courant);
  const TorusProfile profile{spectrum};
  best.value = profile(probe.theta, probe.theta_y);
  if (std::hypot(probe.theta, probe.theta_y) < 2.0 * kSmall2D) {
    // Near the origin the margin is the rays' model: the largest limit of the full sweep's rays.
    const TorusGrid& grid = tori_[static_cast<std::size_t>(probe.family)]->fine;
    for (const int q : grid.unique_rays)
      if (const double v = profile.ray(grid.phi(q)).first; v > best.value)
        best.value = v, best.kind = L2Probe::ray, best.phi = grid.phi(q);
    if (best.kind == L2Probe::ray) best.theta = best.theta_y = 0.0;
    return best;
  }
  GslErrorsAsCodes guard;
  refine_torus_maximum(profile, probe.theta, probe.theta_y, std::numbers::pi / kFine.scan, best);
  best.theta = std::abs(best.theta);
  return best;
}

double L2Criterion::spectral_radius(double courant, double theta, double theta_y) {
  double rho = 0.0;
  for (auto& f : families_) {
    f.set_courant(courant);
    rho = std::max(rho, dim_ == 1 ? f.radius(theta) : f.radius(theta, theta_y));
  }
  return rho;
}

MonotoneMargin monotone_margin(const OneStepMap& map, double courant) {
  MonotoneMargin worst{-1.0, 0, 0};
  bool first = true;
  for (std::size_t f = 0; f < map.families.size(); ++f) {
    const auto& family = map.families[f];
    Eigen::VectorXd row_sums = Eigen::VectorXd::Zero(family.size);
    for (std::size_t i = 0; i < family.offsets.size(); ++i)
      row_sums += family.block(i, courant).cwiseAbs().rowwise().sum();
    for (int r = 0; r < family.size; ++r)
      if (first || row_sums[r] - 1.0 > worst.value) {
        worst = {row_sums[r] - 1.0, static_cast<int>(f), r};
        first = false;
      }
  }
  return worst;
}

}  // namespace dgmpm::stability
