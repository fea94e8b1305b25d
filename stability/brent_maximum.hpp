#pragma once
// One-dimensional maximisation shared by the criteria (the 1D margin's profile, the 2D rays) and
// the growth search (along a line's normal, the 1D scan).

#include "stability/gsl_guard.hpp"

#include <gsl/gsl_min.h>

namespace dgmpm::stability {

// The maximum of f on (left, right) by Brent, from a bracket: f(middle) above f at both ends,
// else nothing is done (a flat or monotone stretch keeps its sampled value). `value` and `where`
// are replaced only by a larger value. x_tolerance: the width at which the bracket is final.
template <class F>
void brent_maximum(const F& f, double left, double middle, double right, double f_left,
                   double f_middle, double f_right, double x_tolerance, double& value,
                   double& where) {
  if (!(f_middle > f_left && f_middle > f_right)) return;
  GslErrorsAsCodes guard;
  gsl_function negated{[](double x, void* d) { return -(*static_cast<const F*>(d))(x); },
                       const_cast<F*>(&f)};
  gsl_min_fminimizer* s = gsl_min_fminimizer_alloc(gsl_min_fminimizer_brent);
  if (gsl_min_fminimizer_set_with_values(s, &negated, middle, -f_middle, left, -f_left, right,
                                         -f_right) == GSL_SUCCESS) {
    for (int it = 0; it < 60; ++it) {
      if (gsl_min_fminimizer_iterate(s) != GSL_SUCCESS) break;
      if (gsl_min_test_interval(gsl_min_fminimizer_x_lower(s), gsl_min_fminimizer_x_upper(s),
                                x_tolerance, 0.0) == GSL_SUCCESS)
        break;
    }
    if (const double v = -gsl_min_fminimizer_f_minimum(s); v > value)
      value = v, where = gsl_min_fminimizer_x_minimum(s);
  }
  gsl_min_fminimizer_free(s);
}

}  // namespace dgmpm::stability
