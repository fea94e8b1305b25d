#pragma once
// The largest C* such that every C in (0, C*] passes (docs/method.md, "Stability"): the passing set
// need not be an interval, so C is scanned upward from 0 and only the first transition is refined.
// Works on any margin function, e.g. the von Neumann criteria or an ARPACK spectral radius minus
// one.

#include <functional>

namespace dgmpm::stability {

struct SearchOptions {
  double scan_step = 0.01;          // the scan cannot see a failing window narrower than this
  double max_courant = 4.0;         // nothing failing up to here: reported as unbounded
  double courant_tolerance = 1e-9;  // width of the final bracket
  int significant_digits = 7;       // C* rounded to these (0: not rounded), never up past a limit
  double margin_tolerance = 0.0;    // C passes when margin(C) <= margin_tolerance
  // Refine by bisection alone, for margins flat below the limit (a spectral radius minus one is 0
  // up to C*): Brent's interpolation gains nothing there, and its minimal steps off the passing
  // end cost an evaluation each.
  bool bisect = false;
};

struct SearchResult {
  double courant = 0.0;  // C*: passes, as does every scanned C below it (rounded: SearchOptions)
  double failing_courant = 0.0;  // fails, within courant_tolerance above C*
  bool bounded = true;           // false: nothing failed up to max_courant (courant = max)
  // C* rounded down to SearchOptions::significant_digits; courant is above it when it was rounded
  // up (to a value that passes with a tenth of the tolerance).
  double rounded_down = 0.0;
  int evaluations = 0;
};

// margin(C) is called for C in (0, max_courant]; C = 0 is taken to pass. A margin may stop early
// once it knows it exceeds the tolerance; full_margin (default: margin) is then the margin in
// full, used where its value matters (C* is made conservative from it: see courant_search.cpp).
SearchResult search_admissible_courant(const std::function<double(double)>& margin,
                                       const SearchOptions& options,
                                       const std::function<double(double)>& full_margin = {});

// What search_admissible_courant does after its scan: lo (>= 0; 0 is taken to pass) passes, hi
// fails; the first transition in between is refined and C* made conservative. (The 2D L2 search
// scans with a cheap margin and refines with a few probes of the full one.)
SearchResult refine_admissible_courant(const std::function<double(double)>& margin, double lo,
                                       double hi, const SearchOptions& options,
                                       const std::function<double(double)>& full_margin = {});

}  // namespace dgmpm::stability
