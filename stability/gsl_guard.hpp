#pragma once
// GSL aborts on errors by default; the analysis checks every return code instead. GSL's handler
// is global: the first guard in turns it off and the last one out restores it, so analyses may
// run on several threads at once (the automatic time step analyses a box's corners so).

#include <gsl/gsl_errno.h>

#include <mutex>

namespace dgmpm::stability {

class GslErrorsAsCodes {
 public:
  GslErrorsAsCodes() {
    const std::lock_guard<std::mutex> lock(state().mutex);
    if (state().active++ == 0) state().previous = gsl_set_error_handler_off();
  }
  ~GslErrorsAsCodes() {
    const std::lock_guard<std::mutex> lock(state().mutex);
    if (--state().active == 0) gsl_set_error_handler(state().previous);
  }
  GslErrorsAsCodes(const GslErrorsAsCodes&) = delete;
  GslErrorsAsCodes& operator=(const GslErrorsAsCodes&) = delete;

 private:
  struct State {
    std::mutex mutex;
    int active = 0;
    gsl_error_handler_t* previous = nullptr;
  };
  static State& state() {
    static State s;
    return s;
  }
};

}  // namespace dgmpm::stability
