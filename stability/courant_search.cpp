#include "stability/courant_search.hpp"

#include "stability/gsl_guard.hpp"

#include <cmath>
#include <gsl/gsl_roots.h>
#include <stdexcept>
#include <string>

namespace dgmpm::stability {
namespace {

struct Shifted {
  const std::function<double(double)>& margin;
  double tolerance;
  int& evaluations;
};

double shifted_margin(double courant, void* data) {
  auto& s = *static_cast<Shifted*>(data);
  ++s.evaluations;
  return s.margin(courant) - s.tolerance;
}

// C* from the final bracket [lo, hi]. A margin tolerance lets C a little above the true limit
// pass: lo may sit above it by margin(lo) / (the margin's slope past the limit), so twice that
// (slope measured just above hi, margins evaluated in full) is taken off, never below the last
// scanned C that passed. A larger overshoot than 1e-5 lo means a margin that grows so slowly past
// the limit that the limit is the tolerance's (a weak instability at every C): lo is kept. The
// result is rounded to `digits` significant digits: down, or up only to a value that passes with
// a tenth of the tolerance (a neutral limit, as at an exact Courant number 1, then comes back as
// exactly 1). `rounded_down` receives the value rounded down.
double conservative_courant(double lo, double hi, double scanned,
                            const std::function<double(double)>& margin, double tolerance,
                            int digits, double& rounded_down) {
  rounded_down = lo;
  if (!(lo > 0.0)) return lo;
  double c = lo;
  if (const double at_lo = margin(lo); at_lo > 0.0) {
    const double probe = hi + std::max(1e-4 * hi, hi - lo);
    const double at_probe = margin(probe);
    const double overshoot = 2.0 * at_lo * (probe - lo) / (at_probe - at_lo);
    if (at_probe > at_lo && overshoot <= 1e-5 * lo) c = std::max(scanned, lo - overshoot);
  }
  rounded_down = c;
  if (digits <= 0) return c;
  // Divided by an exact power of ten, so that 0.9839554 prints as such.
  const double scale = std::pow(10.0, (digits - 1) - std::floor(std::log10(c)));
  const double nearest = std::round(c * scale) / scale;
  rounded_down = std::floor(c * scale) / scale;
  if (nearest <= c) return rounded_down = nearest;
  if (nearest < hi && margin(nearest) <= 0.1 * tolerance) return nearest;
  return rounded_down;
}

}  // namespace

SearchResult search_admissible_courant(const std::function<double(double)>& margin,
                                       const SearchOptions& options,
                                       const std::function<double(double)>& full_margin) {
  if (!(options.scan_step > 0.0 && options.max_courant > 0.0 && options.courant_tolerance > 0.0))
    throw std::invalid_argument("search_admissible_courant: steps and bounds must be positive");
  SearchResult result;
  Shifted shifted{margin, options.margin_tolerance, result.evaluations};

  // Scan: the first scanned C that fails brackets the first transition with the last that passed.
  double lo = 0.0, hi = 0.0;
  bool found = false;
  const int steps = static_cast<int>(std::ceil(options.max_courant / options.scan_step - 1e-9));
  for (int k = 1; k <= steps && !found; ++k) {
    const double c = std::min(k * options.scan_step, options.max_courant);
    const double f = shifted_margin(c, &shifted);
    if (f > 0.0) {
      hi = c, found = true;
    } else {
      lo = c;
    }
  }
  if (!found) {
    result.courant = result.failing_courant = result.rounded_down = options.max_courant;
    result.bounded = false;
    return result;
  }
  SearchResult refined = refine_admissible_courant(margin, lo, hi, options, full_margin);
  refined.evaluations += result.evaluations;
  return refined;
}

SearchResult refine_admissible_courant(const std::function<double(double)>& margin, double lo,
                                       double hi, const SearchOptions& options,
                                       const std::function<double(double)>& full_margin) {
  SearchResult result;
  Shifted shifted{margin, options.margin_tolerance, result.evaluations};
  const double scanned = lo;
  if (!(hi > lo && lo >= 0.0))
    throw std::invalid_argument("refine_admissible_courant: needs 0 <= lo < hi, got lo = " +
                                std::to_string(lo) + ", hi = " + std::to_string(hi));
  // Refine: Brent keeps a sign change in its bracket, not necessarily the first one when several
  // transitions hide between two scan points; both ends are checked, and the search goes on in
  // the part of the bracket that still starts passing and ends failing.
  GslErrorsAsCodes guard;
  gsl_function f{&shifted_margin, &shifted};
  gsl_root_fsolver* solver = gsl_root_fsolver_alloc(gsl_root_fsolver_brent);
  while (hi - lo > options.courant_tolerance) {
    double x_lower = lo, x_upper = hi;
    // The solver evaluates both ends, and C = 0 is never evaluated: bisect first in that case.
    if (!options.bisect && lo > 0.0 && gsl_root_fsolver_set(solver, &f, lo, hi) == GSL_SUCCESS) {
      for (int it = 0; it < 100; ++it) {
        if (gsl_root_fsolver_iterate(solver) != GSL_SUCCESS) break;
        x_lower = gsl_root_fsolver_x_lower(solver);
        x_upper = gsl_root_fsolver_x_upper(solver);
        if (x_upper - x_lower <= options.courant_tolerance) break;
      }
    }
    if (x_lower == lo && x_upper == hi) {  // no progress: bisect
      const double mid = 0.5 * (lo + hi);
      (shifted_margin(mid, &shifted) > 0.0 ? hi : lo) = mid;
      continue;
    }
    const bool lower_passes = shifted_margin(x_lower, &shifted) <= 0.0;
    const bool upper_passes = shifted_margin(x_upper, &shifted) <= 0.0;
    if (!lower_passes)
      hi = x_lower;
    else if (upper_passes)
      lo = x_upper;
    else
      lo = x_lower, hi = x_upper;
  }
  gsl_root_fsolver_free(solver);
  const auto& full = full_margin ? full_margin : margin;
  result.courant = conservative_courant(
      lo, hi, scanned,
      [&](double c) {
        ++result.evaluations;
        return full(c);
      },
      options.margin_tolerance, options.significant_digits, result.rounded_down);
  result.failing_courant = hi;
  return result;
}

}  // namespace dgmpm::stability
