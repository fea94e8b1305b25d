#include "stability/admissible_courant.hpp"

#include "stability/criteria.hpp"

#include <algorithm>
#include <cmath>
#include <limits>
#include <numbers>
#include <stdexcept>

namespace dgmpm::stability {
namespace {

// The 2D L2 search. A full margin (kFine in criteria.cpp) costs about a thousand eigenproblems,
// so C is scanned with the coarse margin; the probe that fails first is sharpened and its own
// transition refined, which gives a candidate C*; one full margin at the candidate decides. When
// it fails, what failed joins the probes and the refinement starts again below the candidate.
// `critical` receives the probe that fails first just above C*.
SearchResult search_torus(L2Criterion& l2, const SearchOptions& options, L2Margin& critical) {
  const double tolerance = options.margin_tolerance, step = options.scan_step;
  int evaluations = 0;
  double lo = 0.0, hi = 0.0;
  int scanned = 0;  // lo = scanned * step
  std::vector<L2Margin> probes;
  const int steps = static_cast<int>(std::ceil(options.max_courant / step - 1e-9));
  for (int k = 1; k <= steps; ++k) {
    const double c = std::min(k * step, options.max_courant);
    const L2Margin m = l2.coarse_margin(c, tolerance);
    ++evaluations;
    if (m.value > tolerance) {
      hi = c;
      probes.push_back(m);
      break;
    }
    lo = c, scanned = k;
  }
  if (probes.empty()) {
    const L2Margin m = l2.margin(options.max_courant, tolerance);
    ++evaluations;
    if (m.value <= tolerance) {
      SearchResult unbounded;
      unbounded.courant = unbounded.failing_courant = unbounded.rounded_down = options.max_courant;
      unbounded.bounded = false;
      unbounded.evaluations = evaluations;
      return unbounded;
    }
    hi = options.max_courant;
    probes.push_back(m);
  }
  const auto local = [&](double c) {
    double worst = -std::numeric_limits<double>::infinity();
    for (const auto& p : probes) worst = std::max(worst, l2.probe_margin(c, p));
    return worst;
  };
  for (int round = 0; round < 8; ++round) {
    probes.back() = l2.sharpen(hi, probes.back());
    // The probes' first transition: below lo if one of them already fails there, or if the
    // candidate that failed lies below lo (rounded down past the scan point).
    while (scanned > 0 && (hi <= lo || local(lo) > tolerance))
      hi = std::min(hi, lo), lo = --scanned * step;
    SearchResult s = refine_admissible_courant(local, lo, hi, options);
    evaluations += s.evaluations;
    // Rounded up: the full margin must pass with a tenth of the tolerance there, else C* is the
    // value rounded down, which must pass with the tolerance.
    const bool rounded_up = s.courant > s.rounded_down;
    L2Margin m = l2.checked_margin(s.courant, rounded_up ? 0.1 * tolerance : tolerance);
    ++evaluations;
    if (rounded_up && m.value > 0.1 * tolerance && m.value <= tolerance) {
      s.courant = s.rounded_down;
      m = l2.checked_margin(s.courant, tolerance);
      ++evaluations;
    }
    if (m.value <= (s.courant > s.rounded_down ? 0.1 : 1.0) * tolerance) {
      critical = probes.front();
      double worst = -std::numeric_limits<double>::infinity();
      for (const auto& p : probes)
        if (const double v = l2.probe_margin(s.failing_courant, p); v > worst)
          worst = v, critical = p;
      s.evaluations = evaluations;
      return s;
    }
    probes.push_back(m);
    hi = s.courant;
  }
  // Not settled by a few probes: the full margin everywhere.
  SearchResult s =
      search_admissible_courant([&](double c) { return l2.checked_margin(c, tolerance).value; },
                                options, [&](double c) { return l2.checked_margin(c).value; });
  critical = l2.checked_margin(s.failing_courant);
  s.evaluations += evaluations;
  return s;
}

}  // namespace

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
  if (criterion == Criterion::budget)
    throw std::invalid_argument("the budget criterion needs a growth budget: budgeted_courant");
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
    L2Margin m;
    if (map.setting.dim > 1) {
      s = search_torus(l2, options, m);
    } else {
      s = search_admissible_courant([&](double c) { return l2.margin(c, tolerance).value; },
                                    options, [&](double c) { return l2.margin(c).value; });
      if (s.bounded) m = l2.margin(s.failing_courant);
    }
    if (s.bounded) {
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

BudgetedCourant budgeted_courant(const OneStepMap& map, const CourantResult& strict,
                                 const GrowthBudget& budget) {
  BudgetedCourant r;
  r.courant = r.strict = strict.courant;
  r.bounded = strict.bounded;
  if (!strict.bounded) return r;
  L2Criterion l2(map);
  const auto over = [&](double c) {
    ++r.evaluations;
    const L2Growth g = l2.growth(c);
    return std::pair{g.value - budget.allowance(c), g.value};
  };
  // Just above the L2 limit (1% of it): the onset of an instability (its growth rises from
  // nothing there: 1e-4 per step for two particles, 2e-2 for a centred one) is not budgeted; a
  // weak growth, present at every C and vetoed by L2, is (1e-13 there for an off-centre particle
  // with the paper's RK2).
  // The mode that failed first in the L2 search, or the shortest waves, usually show it in a
  // few symbol evaluations (a growth search costs hundreds).
  const double above = strict.courant * 1.01;
  constexpr double pi = std::numbers::pi;
  const double probes[][2] = {{strict.critical_theta, strict.critical_theta_y},
                              {pi, 0.0},
                              {0.0, pi},
                              {pi, pi},
                              {pi, 0.5 * pi},
                              {0.5 * pi, pi}};
  for (const auto& t : probes) {
    if (map.setting.dim == 1 && t[1] != 0.0) continue;
    if (l2.spectral_radius(above, t[0], t[1]) - 1 > kOnsetGrowth) return r;
  }
  const auto [excess, growth_above] = over(above);
  if (excess > 0.0 || growth_above > kOnsetGrowth) return r;
  // Scan upward from the L2 limit (the scan's step: what fails between two points is not seen,
  // as for the L2 search), then bisect the first transition to a relative 1e-4.
  // Never above 1 (a wave would cross more than a cell per step, past what the face fluxes
  // exchange), unless the L2 limit itself is.
  const SearchOptions options = default_search_options(Criterion::l2);
  const double step = map.setting.dim > 1 ? kL2ScanStep2D : options.scan_step;
  const double top = std::max(1.0, strict.courant);
  double lo = above, hi = 0.0;
  if (lo >= top) return r;
  for (double c = lo + step;; c += step) {
    c = std::min(c, top);
    if (over(c).first > 0.0) {
      hi = c;
      break;
    }
    lo = c;
    if (c >= top) {
      r.courant = lo;
      r.extended = true;
      r.growth = std::max(0.0, l2.growth(lo).value);
      return r;
    }
  }
  while (hi - lo > 1e-4 * lo) {
    const double mid = 0.5 * (lo + hi);
    (over(mid).first > 0.0 ? hi : lo) = mid;
  }
  r.courant = lo;
  r.extended = true;
  r.growth = std::max(0.0, over(lo).second);
  return r;
}

BudgetedCourant budgeted_courant(const CellLayout& layout, const AnalysisSetting& setting,
                                 const GrowthBudget& budget) {
  const OneStepMap map = build_one_step_map(layout, setting);
  return budgeted_courant(
      map, admissible_courant(map, Criterion::l2, default_search_options(Criterion::l2)), budget);
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
