#pragma once
// GSL aborts on errors by default; the analysis checks every return code instead.

#include <gsl/gsl_errno.h>

namespace dgmpm::stability {

class GslErrorsAsCodes {
 public:
  GslErrorsAsCodes() : previous_(gsl_set_error_handler_off()) {}
  ~GslErrorsAsCodes() { gsl_set_error_handler(previous_); }
  GslErrorsAsCodes(const GslErrorsAsCodes&) = delete;
  GslErrorsAsCodes& operator=(const GslErrorsAsCodes&) = delete;

 private:
  gsl_error_handler_t* previous_;
};

}  // namespace dgmpm::stability
