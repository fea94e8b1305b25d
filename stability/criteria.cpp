#include "stability/criteria.hpp"

#include "stability/gsl_guard.hpp"

#include <Eigen/Eigenvalues>
#include <Eigen/SVD>
#include <cmath>
#include <complex>
#include <gsl/gsl_min.h>
#include <numbers>

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

FamilySpectrum::FamilySpectrum(const StencilFamily& family) : offsets_(family.offsets) {
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

double negated_profile(double theta, void* profile) {
  return -(*static_cast<const ThetaProfile*>(profile))(theta);
}

// Maximum of the profile in (left, right) near a grid maximum at `middle`.
void refine_maximum(const ThetaProfile& profile, double left, double middle, double right,
                    double f_left, double f_middle, double f_right, double& best,
                    double& best_theta) {
  if (!(f_middle > f_left && f_middle > f_right)) return;  // flat: keep the grid value
  GslErrorsAsCodes guard;
  gsl_function f{&negated_profile, const_cast<ThetaProfile*>(&profile)};
  gsl_min_fminimizer* s = gsl_min_fminimizer_alloc(gsl_min_fminimizer_brent);
  if (gsl_min_fminimizer_set_with_values(s, &f, middle, -f_middle, left, -f_left, right,
                                         -f_right) == GSL_SUCCESS) {
    for (int it = 0; it < 60; ++it) {
      if (gsl_min_fminimizer_iterate(s) != GSL_SUCCESS) break;
      if (gsl_min_test_interval(gsl_min_fminimizer_x_lower(s), gsl_min_fminimizer_x_upper(s), 1e-7,
                                0.0) == GSL_SUCCESS)
        break;
    }
    const double value = -gsl_min_fminimizer_f_minimum(s);
    if (value > best) best = value, best_theta = gsl_min_fminimizer_x_minimum(s);
  }
  gsl_min_fminimizer_free(s);
}

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
      refine_maximum(profile, thetas[j - 1], thetas[j], thetas[j + 1], values[j - 1], values[j],
                     values[j + 1], best, best_theta);
  return {best, best_theta, 0};
}

}  // namespace

L2Criterion::L2Criterion(const OneStepMap& map) {
  for (const auto& f : map.families) families_.emplace_back(f);
}

L2Margin L2Criterion::margin(double courant) {
  L2Margin worst;
  for (std::size_t f = 0; f < families_.size(); ++f) {
    L2Margin m = family_margin(families_[f], courant);
    m.family = static_cast<int>(f);
    if (f == 0 || m.value > worst.value) worst = m;
  }
  return worst;
}

double L2Criterion::spectral_radius(double courant, double theta) {
  double rho = 0.0;
  for (auto& f : families_) {
    f.set_courant(courant);
    rho = std::max(rho, f.radius(theta));
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
