#pragma once
// Exact solution of the 1D linear elastic bar (docs/method.md, "Equations"): rho v_t = sigma_x,
// sigma_t = E v_x on [a, b], one homogeneous material, piecewise-constant initial stress and
// velocity, ends free, fixed, prescribed stress sigma_d(t) or prescribed velocity v_d(t), or a
// periodic bar.
//
// Method: the Riemann invariants w+ = sigma - Z v (moves at +c) and w- = sigma + Z v (moves at -c)
// are traced back along their characteristics, reflecting at the ends, down to t = 0. A reflection
// is affine: outgoing = s * incoming + g(tau), with
//   free: s = -1, g = 0;   fixed: s = +1, g = 0;   stress sigma_d: s = -1, g = 2 sigma_d(tau);
//   velocity v_d: s = +1, g = -2 Z v_d(tau) at the left end (w+ = w- - 2 Z v_d),
//                          g = +2 Z v_d(tau) at the right end (w- = w+ + 2 Z v_d).
// The prescribed value is the stress sigma at the end (not the traction sigma n), the same
// convention as the ghost states of physics/elastic_bar.hpp, so a positive value pulls the bar
// (tension) at both ends. Cost of one evaluation: O(log segments) without boundary sources
// (free/fixed/periodic), plus O(number of reflections * log table size) with traction or velocity
// ends.
//
// Discontinuities: stress and velocity are the limit from the right in x (x -> x+), at any time,
// including fronts that have reflected or that were emitted from a corner at t = 0. At x = b, where
// no right limit exists in the bar, the limit from the left. Time tables are continuous except at
// repeated times (steps); at a step time the table's own value is used.

#include "../boundary.hpp"

#include <algorithm>
#include <cmath>
#include <stdexcept>
#include <string>
#include <utility>
#include <vector>

namespace dgmpm::exact {

// Initial data on [x0, x1): stress and velocity.
struct Segment {
  double x0, x1, sigma, v;
};

struct BarState {
  double stress, velocity;
};

class ElasticBarSolution {
 public:
  // Bar [a, b] with the given ends. The segments (any order) must cover [a, b] without gap or
  // overlap; ends may differ by at most 1e-12 (b - a) from their neighbours' (rounding of scene
  // arithmetic), the breakpoints kept are a, the x0 of the 2nd to last segments, and b.
  // Throws std::invalid_argument on bad input.
  ElasticBarSolution(double a, double b, double young, double density, std::vector<Segment> initial,
                     BoundaryCondition<1> left, BoundaryCondition<1> right)
      : ElasticBarSolution(a, b, young, density, std::move(initial), false) {
    ends_[0] = make_end(left, 0, "left");
    ends_[1] = make_end(right, 1, "right");
    has_source_ = ends_[0].gain != 0.0 || ends_[1].gain != 0.0;
    for (const End& e : ends_)
      if (e.gain != 0.0) t_const_ = std::max(t_const_, e.table.times.back());
  }

  // Periodic bar of period b - a.
  static ElasticBarSolution periodic(double a, double b, double young, double density,
                                     std::vector<Segment> initial) {
    return ElasticBarSolution(a, b, young, density, std::move(initial), true);
  }

  // Requires a <= x <= b and t >= 0 with c t <= 1e9 (b - a); throws std::out_of_range otherwise.
  BarState state(double x, double t) const {
    check_point(x, t);
    const int side = (x < b_ || periodic_) ? +1 : -1;
    const auto [wp, wm] = invariants(x, phase(t), side);
    return {0.5 * (wp + wm), (wm - wp) / (2.0 * z_)};
  }
  double stress(double x, double t) const { return state(x, t).stress; }
  double velocity(double x, double t) const { return state(x, t).velocity; }

  // Total energy per unit cross-section, integral over [a, b] of rho v^2 / 2 + sigma^2 / (2 E)
  // = (w+^2 + w-^2) / (4 E). Both invariants are linear in x between the current positions of the
  // fronts (initial jumps, corners, kinks of the time tables), which are enumerated; 2-point Gauss
  // on each piece is then exact up to round-off.
  double energy(double t) const {
    check_point(a_, t);
    const Phase ph = phase(t);
    const double p = ph.p, L = length_;
    // Front positions modulo L, each family (see trace() for D = j L + s).
    std::vector<double> cuts;
    auto add = [&](double x) {
      for (double i = -2.0; i <= 2.0; i += 1.0) cuts.push_back(x + i * L);
    };
    for (double xb : xs_) {
      if (periodic_) {
        add(xb + p);
        add(xb - p);
      } else {
        for (double off : {xb - a_, b_ - xb}) {
          add(a_ + p - off);
          add(b_ - p + off);
        }
      }
    }
    if (!periodic_)
      for (const End& e : ends_) {
        if (e.gain == 0.0) continue;
        for (double tk : e.table.times) {
          // Reflection k at time tk: D = c tk + k L.
          const double q = std::fmod(c_ * tk, L);
          add(a_ + p - q);
          add(b_ - p + q);
        }
      }
    std::sort(cuts.begin(), cuts.end());
    const double g = 0.5 / std::sqrt(3.0);
    double sum = 0.0, x0 = a_;
    auto f = [&](double x) {
      const auto [wp, wm] = invariants(x, ph, +1);
      return wp * wp + wm * wm;
    };
    cuts.push_back(b_);
    for (double x1 : cuts) {
      if (x1 <= x0) continue;
      x1 = std::min(x1, b_);
      const double mid = 0.5 * (x0 + x1), h = x1 - x0;
      sum += 0.5 * h * (f(mid - g * h) + f(mid + g * h));
      x0 = x1;
      if (x0 >= b_) break;
    }
    return sum / (4.0 * young_);
  }

  double wave_speed() const { return c_; }
  double impedance() const { return z_; }
  double left() const { return a_; }
  double right() const { return b_; }
  bool is_periodic() const { return periodic_; }

 private:
  enum Family { plus = 0, minus = 1 };

  struct End {
    double s = -1.0;  // outgoing = s * incoming + gain * table(tau)
    double gain = 0.0;
    TimeTable<1> table;
    double last = 0.0;  // gain * table value after its last time
  };

  ElasticBarSolution(double a, double b, double young, double density, std::vector<Segment> initial,
                     bool periodic)
      : a_(a), b_(b), young_(young), periodic_(periodic) {
    if (!std::isfinite(a) || !std::isfinite(b) || !(a < b))
      throw std::invalid_argument("exact bar: need finite a < b, got a = " + std::to_string(a) +
                                  ", b = " + std::to_string(b));
    if (!std::isfinite(young) || !(young > 0.0))
      throw std::invalid_argument("exact bar: Young's modulus must be positive, got " +
                                  std::to_string(young));
    if (!std::isfinite(density) || !(density > 0.0))
      throw std::invalid_argument("exact bar: density must be positive, got " +
                                  std::to_string(density));
    length_ = b - a;
    c_ = std::sqrt(young / density);
    z_ = std::sqrt(young * density);
    set_initial(std::move(initial));
  }

  void set_initial(std::vector<Segment> segs) {
    if (segs.empty()) throw std::invalid_argument("exact bar: no initial segment");
    for (const Segment& s : segs) {
      if (!std::isfinite(s.x0) || !std::isfinite(s.x1) || !std::isfinite(s.sigma) ||
          !std::isfinite(s.v))
        throw std::invalid_argument("exact bar: non-finite value in a segment");
      if (!(s.x1 > s.x0))
        throw std::invalid_argument("exact bar: segment [" + std::to_string(s.x0) + ", " +
                                    std::to_string(s.x1) + ") is empty");
    }
    std::sort(segs.begin(), segs.end(),
              [](const Segment& p, const Segment& q) { return p.x0 < q.x0; });
    const double tol = 1e-12 * length_;
    auto mismatch = [&](double x, double y) { return !(std::abs(x - y) <= tol); };
    if (mismatch(segs.front().x0, a_) || mismatch(segs.back().x1, b_))
      throw std::invalid_argument("exact bar: segments span [" + std::to_string(segs.front().x0) +
                                  ", " + std::to_string(segs.back().x1) + "], not the bar [" +
                                  std::to_string(a_) + ", " + std::to_string(b_) + "]");
    xs_ = {a_};
    for (std::size_t k = 0; k < segs.size(); ++k) {
      if (k > 0) {
        if (mismatch(segs[k - 1].x1, segs[k].x0))
          throw std::invalid_argument("exact bar: gap or overlap between " +
                                      std::to_string(segs[k - 1].x1) + " and " +
                                      std::to_string(segs[k].x0));
        xs_.push_back(segs[k].x0);
      }
      w_[plus].push_back(segs[k].sigma - z_ * segs[k].v);
      w_[minus].push_back(segs[k].sigma + z_ * segs[k].v);
    }
    xs_.push_back(b_);
    for (std::size_t k = 1; k < xs_.size(); ++k)
      if (!(xs_[k] > xs_[k - 1]))
        throw std::invalid_argument("exact bar: segment shorter than the matching tolerance");
  }

  End make_end(const BoundaryCondition<1>& bc, int side, const char* name) const {
    End e;
    const std::string where = std::string("exact bar: ") + name + " end: ";
    switch (bc.kind) {
      case BoundaryKind::free:
        return e;
      case BoundaryKind::fixed:
        e.s = 1.0;
        return e;
      case BoundaryKind::traction:
        e.s = -1.0;
        e.gain = 2.0;
        break;
      case BoundaryKind::velocity:
        e.s = 1.0;
        e.gain = (side == 0 ? -2.0 : 2.0) * z_;
        break;
      default:
        throw std::invalid_argument(where + "unknown boundary kind");
    }
    const TimeTable<1>& tt = bc.value;
    if (tt.values.empty() || tt.values.size() != tt.times.size())
      throw std::invalid_argument(where + "time table needs as many times as values, at least one");
    for (std::size_t k = 0; k < tt.times.size(); ++k) {
      if (!std::isfinite(tt.times[k]) || !std::isfinite(tt.values[k][0]))
        throw std::invalid_argument(where + "non-finite entry in the time table");
      if (k > 0 && tt.times[k] < tt.times[k - 1])
        throw std::invalid_argument(where + "time table times must not decrease");
    }
    e.table = tt;
    e.last = e.gain * tt.values.back()[0];
    return e;
  }

  void check_point(double x, double t) const {
    if (!(x >= a_ && x <= b_))
      throw std::out_of_range("exact bar: x = " + std::to_string(x) + " outside [" +
                              std::to_string(a_) + ", " + std::to_string(b_) + "]");
    // Beyond that, reflection counts stop being exact integers in double and loops get long.
    if (!(t >= 0.0 && c_ * t <= 1e9 * length_))
      throw std::out_of_range("exact bar: t = " + std::to_string(t) +
                              " outside [0, 1e9 (b - a) / c]");
  }

  // Initial invariant at y, limit from the right (side > 0) or the left (side < 0).
  double initial(int fam, double y, int side) const {
    const auto first = xs_.begin() + 1, last = xs_.end() - 1;  // interior breakpoints
    const auto it = side > 0 ? std::upper_bound(first, last, y) : std::lower_bound(first, last, y);
    return w_[fam][static_cast<std::size_t>(it - first)];
  }

  // Periodic image of u in [a, b]; a and b are the same point, seen from the side given.
  double wrap(double u, int side) const {
    double r = std::fmod(u - a_, length_);
    if (r < 0.0) r += length_;
    if (r >= length_) r -= length_;
    if (side < 0 && r == 0.0) r = length_;
    return a_ + r;
  }

  // c t = j L + p with p in [0, L) exact (fmod), so that fronts far in time stay consistent.
  struct Phase {
    double j, p;
  };
  Phase phase(double t) const {
    const double ct = c_ * t, p = std::fmod(ct, length_);
    return {std::round((ct - p) / length_), p};
  }

  // (w+, w-) at x, limit on the given side in x.
  std::pair<double, double> invariants(double x, const Phase& ph, int side) const {
    if (periodic_)
      return {initial(plus, wrap(x - ph.p, side), side),
              initial(minus, wrap(x + ph.p, side), side)};
    // D = c t - (distance to the end reached first backwards): dD/dx = -1 for w+, +1 for w-.
    return {trace(0, ph.j, ph.p - (x - a_), -side), trace(1, ph.j, ph.p - (b_ - x), side)};
  }

  // Invariant leaving end `first` (0: w+ at the left end, 1: w- at the right end), traced back
  // D = j L + s further, D / c being the time since that end was reached; D < 0 means the
  // characteristic meets t = 0 inside the bar. `dside` is the side of the limit in D: ties at
  // D = k L are resolved by it, so that a whole evaluation is one-sided.
  double trace(int first, double j, double s, int dside) const {
    const double L = length_;
    const double k = std::floor(s / L);
    double m = j + k, r = s - k * L;  // D = m L + r: m + 1 reflections if m >= 0
    // Bring r into [0, L) against rounding, then resolve the tie r = 0 by the side.
    if (r < 0.0) {
      r += L;
      m -= 1.0;
    }
    if (r >= L) {
      r -= L;
      m += 1.0;
    }
    if (r == 0.0 && dside < 0) {
      r = L;
      m -= 1.0;
    }
    if (m < 0.0) return first == 0 ? initial(plus, b_ - r, -dside) : initial(minus, a_ + r, dside);
    const int last = std::fmod(m, 2.0) != 0.0 ? 1 - first : first;
    // Past the last reflection the characteristic crosses the bar for r, away from that end.
    const double w0 = last == 0 ? initial(minus, a_ + r, dside) : initial(plus, b_ - r, -dside);
    if (!has_source_) {
      // m + 1 reflections alternating from `first`: floor(m / 2) + 1 there, the rest opposite.
      const double n_first = std::floor(m / 2.0) + 1.0, n_other = m + 1.0 - n_first;
      double mult = 1.0;
      if (ends_[first].s < 0.0 && std::fmod(n_first, 2.0) != 0.0) mult = -mult;
      if (ends_[1 - first].s < 0.0 && std::fmod(n_other, 2.0) != 0.0) mult = -mult;
      return mult * w0;
    }
    double acc = 0.0, mult = 1.0, i = 0.0;
    // Reflections after the last knot of both tables see constant values: sum them in pairs
    // (first end, other end), each adding mult * u and multiplying mult by P. Reflection i is at
    // tau_i = ((m - i) L + r) / c; the count below is one short of the bound, to stay safe.
    const double n_const = m - std::ceil((c_ * t_const_ - r) / L);
    if (n_const >= 2.0) {
      const End &f = ends_[first], &o = ends_[1 - first];
      const double pairs = std::floor(n_const / 2.0), u = f.last + f.s * o.last, P = f.s * o.s;
      const bool odd = std::fmod(pairs, 2.0) != 0.0;
      acc = u * (P > 0.0 ? pairs : (odd ? 1.0 : 0.0));
      mult = (P < 0.0 && odd) ? -1.0 : 1.0;
      i = 2.0 * pairs;
    }
    for (; i <= m; i += 1.0) {
      const End& e = ends_[std::fmod(i, 2.0) == 0.0 ? first : 1 - first];
      if (e.gain != 0.0) {
        const double tau = std::max(0.0, ((m - i) * L + r) / c_);  // time of reflection i
        acc += mult * e.gain * e.table(tau)[0];
      }
      mult *= e.s;
    }
    return acc + mult * w0;
  }

  double a_, b_, young_, length_ = 0.0, c_ = 0.0, z_ = 0.0;
  double t_const_ = 0.0;  // boundary values are constant after this time
  bool periodic_ = false, has_source_ = false;
  std::vector<double> xs_;    // breakpoints a = xs_[0] < ... < xs_[n] = b
  std::vector<double> w_[2];  // initial w+ and w- on each segment
  End ends_[2];               // left, right (unused when periodic)
};

}  // namespace dgmpm::exact
