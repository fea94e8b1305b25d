#include "stability/admissible_courant.hpp"

#include "stability/criteria.hpp"

#include <algorithm>
#include <limits>
#include <stdexcept>

namespace dgmpm::stability {

SearchOptions default_search_options(Criterion criterion) {
  SearchOptions o;
  if (criterion == Criterion::l2) {
    o.scan_step = 0.01;
    o.margin_tolerance = kL2MarginTolerance;
  } else {
    o.scan_step = 0.002;  // cheap to evaluate: scan finely
    o.margin_tolerance = kMonotoneMarginTolerance;
  }
  return o;
}

CourantResult admissible_courant(const OneStepMap& map, Criterion criterion,
                                 const SearchOptions& given) {
  CourantResult r;
  SearchResult s;
  // Round-off in the map (large near a nearly massless node with RK2) must not read as a row sum
  // above 1. (The physical eigenvalues of the L2 criterion are far less sensitive to it: the
  // tolerance of criteria.hpp holds there, checked down to 1e-10 from a node.)
  SearchOptions options = given;
  if (criterion == Criterion::monotone)
    options.margin_tolerance = std::max(options.margin_tolerance, map.round_off_level());
  if (criterion == Criterion::l2) {
    L2Criterion l2(map);
    if (map.setting.dim > 1) {
      options.margin_tolerance = std::max(options.margin_tolerance, kL2MarginTolerance2D);
      // A 2D margin costs hundreds of eigenproblems: the scan is coarser than in 1D.
      options.scan_step = std::max(options.scan_step, kL2ScanStep2D);
    }
    const double tolerance = options.margin_tolerance;
    s = search_admissible_courant([&](double c) { return l2.margin(c, tolerance).value; }, options,
                                  [&](double c) { return l2.margin(c).value; });
    if (s.bounded) {
      const L2Margin m = l2.margin(s.failing_courant);
      r.direction = map.families[m.family].direction;
      r.critical_theta = m.theta;
      r.critical_theta_y = m.theta_y;
    }
  } else {
    s = search_admissible_courant([&](double c) { return monotone_margin(map, c).value; }, options);
    if (s.bounded) {
      const MonotoneMargin m = monotone_margin(map, s.failing_courant);
      const auto& family = map.families[m.family];
      r.direction = family.direction;
      r.limiting_particle = family.particle[m.row];
    }
  }
  if (!s.bounded) r.critical_theta = std::numeric_limits<double>::quiet_NaN();
  r.courant = s.courant;
  r.bounded = s.bounded;
  r.failing_courant = s.failing_courant;
  r.evaluations = s.evaluations;
  return r;
}

CourantResult admissible_courant(const CellLayout& layout, TimeScheme scheme, Criterion criterion,
                                 Model model) {
  return admissible_courant(build_one_step_map(layout, scheme, model), criterion,
                            default_search_options(criterion));
}

CourantResult admissible_courant(const CellLayout& layout, const AnalysisSetting& setting,
                                 Criterion criterion) {
  if (setting.dim > 1 && setting.model == Model::elastic && criterion == Criterion::monotone)
    throw std::invalid_argument(
        "the monotone criterion needs scalar waves: the 2D elastic system does not split into "
        "them (use --criterion l2, or --model advection)");
  return admissible_courant(build_one_step_map(layout, setting), criterion,
                            default_search_options(criterion));
}

}  // namespace dgmpm::stability
