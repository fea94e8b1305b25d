#define BOOST_TEST_MODULE exact_bar
#include <boost/test/unit_test.hpp>

#include <dgmpm/exact/elastic_bar.hpp>

#include <algorithm>
#include <cmath>
#include <stdexcept>
#include <vector>

// Expected values are written here from the characteristic formulas by hand (impedance relations,
// reflection rules, work of the end loads), independently of the header's tracing.

using dgmpm::BoundaryCondition;
using dgmpm::BoundaryKind;
using dgmpm::TimeTable;
using dgmpm::exact::ElasticBarSolution;
using dgmpm::exact::Segment;

namespace {

using V1 = Eigen::Matrix<double, 1, 1>;

BoundaryCondition<1> end_of(BoundaryKind k, double value = 0.0) {
  return {k, TimeTable<1>::constant(V1(value))};
}
BoundaryCondition<1> free_end() {
  return end_of(BoundaryKind::free);
}
BoundaryCondition<1> fixed_end() {
  return end_of(BoundaryKind::fixed);
}
BoundaryCondition<1> table_end(BoundaryKind k, std::vector<double> t, std::vector<double> v) {
  BoundaryCondition<1> bc{k, {}};
  bc.value.times = t;
  for (double x : v) bc.value.values.push_back(V1(x));
  return bc;
}

// |actual - expected| <= tol, reported with the point.
void check(double actual, double expected, double tol, double x, double t, const char* what) {
  BOOST_TEST(std::abs(actual - expected) <= tol,
             what << " at x = " << x << ", t = " << t << ": " << actual << " vs " << expected);
}

// Points of [x0, x1] avoiding the ends by a margin.
std::vector<double> points(double x0, double x1, int n = 25, double margin = 1e-6) {
  std::vector<double> p;
  for (int i = 0; i < n; ++i) p.push_back(x0 + margin + (x1 - x0 - 2 * margin) * i / (n - 1));
  return p;
}

double segment_energy(const std::vector<Segment>& segs, double young, double rho) {
  double e = 0.0;
  for (const Segment& s : segs)
    e += (s.x1 - s.x0) * (0.5 * rho * s.v * s.v + s.sigma * s.sigma / (2 * young));
  return e;
}

constexpr double steel_E = 2e11, steel_rho = 7800;

}  // namespace

// Founding paper's two-bar impact.
BOOST_AUTO_TEST_CASE(two_bar_impact_free_ends) {
  const double c = std::sqrt(steel_E / steel_rho), Z = steel_rho * c, v0 = 4e9 / (2 * Z);
  const ElasticBarSolution bar(0.0, 6.0, steel_E, steel_rho, {{0, 3, 0, v0}, {3, 6, 0, -v0}},
                               free_end(), free_end());
  const double s_imp = -Z * v0;  // -2e9: stress of the impact plateau
  BOOST_TEST(std::abs(s_imp + 2e9) < 1e-3);
  const double tol_s = 1e-12 * 2e9, tol_v = 1e-12 * v0;

  // Before the fronts reach the ends: plateau between 3 - ct and 3 + ct.
  for (double t : {0.3 / c, 1.0 / c, 2.9 / c}) {
    const double f = c * t;
    for (double x : points(0, 6, 61)) {
      if (std::abs(std::abs(x - 3) - f) < 1e-6) continue;
      const bool inside = std::abs(x - 3) < f;
      check(bar.stress(x, t), inside ? s_imp : 0.0, tol_s, x, t, "stress");
      check(bar.velocity(x, t), inside ? 0.0 : (x < 3 ? v0 : -v0), tol_v, x, t, "velocity");
    }
  }
  // After reflection at the free ends: released zones of width ct - 3 at each end move apart.
  for (double t : {3.2 / c, 4.5 / c, 5.9 / c}) {
    const double f = c * t - 3;
    for (double x : points(0, 6, 61)) {
      if (std::abs(x - f) < 1e-6 || std::abs(6 - x - f) < 1e-6) continue;
      const bool released = x < f || x > 6 - f;
      check(bar.stress(x, t), released ? 0.0 : s_imp, tol_s, x, t, "stress");
      check(bar.velocity(x, t), released ? (x < 3 ? -v0 : v0) : 0.0, tol_v, x, t, "velocity");
    }
  }
  // Full release at t = 6/c: velocities reversed, no stress (the bars separate).
  const double t6 = 6.0 / c;
  for (double x : points(0, 6, 201)) {
    if (std::abs(x - 3) < 1e-6) continue;
    check(bar.stress(x, t6), 0.0, tol_s, x, t6, "stress");
    check(bar.velocity(x, t6), x < 3 ? -v0 : v0, tol_v, x, t6, "velocity");
  }
  // The linear model carries on in tension: plateau +Z v0 between 3 -+ (ct - 6).
  const double t7 = 7.0 / c;
  check(bar.stress(3.2, t7), Z * v0, tol_s, 3.2, t7, "stress");
  check(bar.velocity(3.2, t7), 0.0, tol_v, 3.2, t7, "velocity");
  // Energy of the initial motion, conserved.
  const double e0 = 6.0 * 0.5 * steel_rho * v0 * v0;
  for (double t : {0.0, 1.0 / c, 3.2 / c, t6, 1000 * 6.0 / c, 1234.567 / c})
    BOOST_TEST(std::abs(bar.energy(t) - e0) <= 1e-12 * e0, "energy at t = " << t);
}

// Bar moving at v0 into a fixed right end: sigma = -Z v0 behind the front, v = 0.
BOOST_AUTO_TEST_CASE(fixed_end_impact) {
  const double c = std::sqrt(steel_E / steel_rho), Z = steel_rho * c, v0 = 10.0, L = 2.0;
  const ElasticBarSolution bar(0, L, steel_E, steel_rho, {{0, L, 0, v0}}, free_end(), fixed_end());
  const double t = 0.5 / c;  // front at L - 0.5
  for (double x : points(0, L, 41)) {
    if (std::abs(x - 1.5) < 1e-6) continue;
    check(bar.stress(x, t), x > 1.5 ? -Z * v0 : 0.0, 1e-12 * Z * v0, x, t, "stress");
    check(bar.velocity(x, t), x > 1.5 ? 0.0 : v0, 1e-12 * v0, x, t, "velocity");
  }
  check(bar.velocity(L, t), 0.0, 1e-12 * v0, L, t, "velocity at the fixed end");
}

// A right-going pulse (w- = 0): stress doubles at a fixed end, velocity doubles at a free end.
BOOST_AUTO_TEST_CASE(pulse_reflections_fixed_and_free) {
  const double c = std::sqrt(steel_E / steel_rho), Z = steel_rho * c, s = -1e8;
  const std::vector<Segment> init = {{0, 0.2, 0, 0}, {0.2, 0.4, s, -s / Z}, {0.4, 1, 0, 0}};
  const ElasticBarSolution fixed(0, 1, steel_E, steel_rho, init, free_end(), fixed_end());
  const ElasticBarSolution freed(0, 1, steel_E, steel_rho, init, free_end(), free_end());
  const double tol_s = 1e-12 * std::abs(s), tol_v = tol_s / Z;
  // t = 0.7/c: incident and reflected pulses overlap on [0.9, 1].
  const double t = 0.7 / c;
  for (double x : points(0.9, 1.0, 11)) {
    check(fixed.stress(x, t), 2 * s, tol_s, x, t, "fixed: doubled stress");
    check(fixed.velocity(x, t), 0.0, tol_v, x, t, "fixed: velocity");
    check(freed.stress(x, t), 0.0, tol_s, x, t, "free: stress");
    check(freed.velocity(x, t), -2 * s / Z, tol_v, x, t, "free: doubled velocity");
  }
  // t = 1/c: fully reflected pulse on [0.6, 0.8], moving left (w+ = 0).
  const double t1 = 1.0 / c;
  for (double x : points(0.6, 0.8, 11)) {
    check(fixed.stress(x, t1), s, tol_s, x, t1, "fixed: reflected stress");
    check(fixed.velocity(x, t1), s / Z, tol_v, x, t1, "fixed: reflected velocity");
    check(freed.stress(x, t1), -s, tol_s, x, t1, "free: reflected stress");
    check(freed.velocity(x, t1), -s / Z, tol_v, x, t1, "free: reflected velocity");
  }
  for (double x : {0.3, 0.5, 0.85, 0.95}) {
    check(fixed.stress(x, t1), 0.0, tol_s, x, t1, "fixed: rest");
    check(freed.velocity(x, t1), 0.0, tol_v, x, t1, "free: rest");
  }
}

// Constant stress sigma_d at the right end of a bar at rest, left end free.
BOOST_AUTO_TEST_CASE(constant_traction_end) {
  const double c = std::sqrt(steel_E / steel_rho), Z = steel_rho * c, sd = 3e8, L = 1.5;
  const ElasticBarSolution bar(0, L, steel_E, steel_rho, {{0, L, 0, 0}}, free_end(),
                               end_of(BoundaryKind::traction, sd));
  const double tol_s = 1e-12 * sd, tol_v = tol_s / Z;
  // Before the left end: sigma_d behind the front, v = +sigma_d / Z (tension pulls to +x).
  const double t = 1.0 / c;
  for (double x : points(0, L, 31)) {
    if (std::abs(x - 0.5) < 1e-6) continue;
    check(bar.stress(x, t), x > 0.5 ? sd : 0.0, tol_s, x, t, "stress");
    check(bar.velocity(x, t), x > 0.5 ? sd / Z : 0.0, tol_v, x, t, "velocity");
  }
  // After the free-end reflection (front back at 0.5): sigma = 0, v = 2 sigma_d / Z near x = 0.
  const double t2 = (L + 0.5) / c;
  check(bar.stress(0.25, t2), 0.0, tol_s, 0.25, t2, "stress");
  check(bar.velocity(0.25, t2), 2 * sd / Z, tol_v, 0.25, t2, "velocity");
  check(bar.stress(1.0, t2), sd, tol_s, 1.0, t2, "stress");
  check(bar.velocity(1.0, t2), sd / Z, tol_v, 1.0, t2, "velocity");
  // Energy = work of sigma_d: v(b) = (2n + 1) sigma_d / Z during the n-th round trip T = 2L/c.
  const double T = 2 * L / c;
  for (double tt : {0.0, 0.3 * T, T, 2.5 * T, 7.0 * T, 500 * T, 512.3456 * T}) {
    const double n = std::floor(tt / T);
    const double work = sd * sd / Z * (n * n * T + (2 * n + 1) * (tt - n * T));
    BOOST_TEST(std::abs(bar.energy(tt) - work) <= 1e-12 * std::max(work, sd * sd / Z * T),
               "energy at t = " << tt << ": " << bar.energy(tt) << " vs work " << work);
    // The end moves with the velocity the work formula uses.
    if (tt > 0 && std::abs(tt / T - std::round(tt / T)) > 1e-3)
      check(bar.velocity(L, tt), (2 * n + 1) * sd / Z, 1e-12 * (2 * n + 1) * sd / Z, L, tt,
            "end velocity");
  }
  // Left-end traction: v = -sigma_d / Z behind the front.
  const ElasticBarSolution left(0, L, steel_E, steel_rho, {{0, L, 0, 0}},
                                end_of(BoundaryKind::traction, sd), free_end());
  check(left.stress(0.3, t), sd, tol_s, 0.3, t, "left traction: stress");
  check(left.velocity(0.3, t), -sd / Z, tol_v, 0.3, t, "left traction: velocity");
}

// Prescribed velocity: right end pulled at v_d (tension Z v_d), left end pushed (compression).
BOOST_AUTO_TEST_CASE(prescribed_velocity_end) {
  const double c = std::sqrt(steel_E / steel_rho), Z = steel_rho * c, vd = 2.5, L = 1.0;
  const double tol_s = 1e-12 * Z * vd, tol_v = 1e-12 * vd;
  const ElasticBarSolution right(0, L, steel_E, steel_rho, {{0, L, 0, 0}}, fixed_end(),
                                 end_of(BoundaryKind::velocity, vd));
  const double t = 0.4 / c;
  check(right.stress(0.8, t), Z * vd, tol_s, 0.8, t, "stress");
  check(right.velocity(0.8, t), vd, tol_v, 0.8, t, "velocity");
  check(right.velocity(L, t), vd, tol_v, L, t, "end velocity");
  check(right.stress(0.5, t), 0.0, tol_s, 0.5, t, "stress ahead");
  // Reflected at the fixed end (2 Z v_d, at rest), then again at the driven end (3 Z v_d, v_d).
  const double t2 = 1.5 / c;
  check(right.stress(0.2, t2), 2 * Z * vd, tol_s, 0.2, t2, "stress");
  check(right.velocity(0.2, t2), 0.0, tol_v, 0.2, t2, "velocity");
  const double t3 = 2.5 / c;
  check(right.stress(0.8, t3), 3 * Z * vd, tol_s, 0.8, t3, "stress");
  check(right.velocity(0.8, t3), vd, tol_v, 0.8, t3, "velocity");
  check(right.stress(0.2, t3), 2 * Z * vd, tol_s, 0.2, t3, "stress");
  // Stress grows by 2 Z v_d per round trip: after n trips, (2n + 1) Z v_d near the driven end.
  const double t4 = 200.25 / c;  // 100 round trips + a quarter crossing
  check(right.stress(0.9, t4), 201 * Z * vd, 201 * tol_s, 0.9, t4, "stress");
  check(right.velocity(0.9, t4), vd, 201 * tol_v, 0.9, t4, "velocity");
  check(right.velocity(0.1, t4), 0.0, 201 * tol_v, 0.1, t4, "velocity");

  const ElasticBarSolution left(0, L, steel_E, steel_rho, {{0, L, 0, 0}},
                                end_of(BoundaryKind::velocity, vd), free_end());
  check(left.stress(0.2, t), -Z * vd, tol_s, 0.2, t, "left: stress");
  check(left.velocity(0.2, t), vd, tol_v, 0.2, t, "left: velocity");
  check(left.velocity(0, t), vd, tol_v, 0, t, "left: end velocity");
}

// Stress ramp sigma_d = alpha t up to T1, then held: linear profile behind the front.
BOOST_AUTO_TEST_CASE(traction_ramp_gives_linear_profile) {
  const double c = std::sqrt(steel_E / steel_rho), Z = steel_rho * c, L = 4.0;
  const double T1 = 2.0 / c, alpha = 1e8 / T1;
  const ElasticBarSolution bar(0, L, steel_E, steel_rho, {{0, L, 0, 0}}, free_end(),
                               table_end(BoundaryKind::traction, {0, T1}, {0, alpha * T1}));
  const auto sd = [&](double tau) { return alpha * std::clamp(tau, 0.0, T1); };
  for (double t : {0.5 / c, 1.7 / c, 3.0 / c, 3.9 / c}) {
    for (double x : points(0, L, 41)) {
      const double tau = t - (L - x) / c;  // emission time at the end of the left-going wave
      const double s = tau > 0 ? sd(tau) : 0.0;
      check(bar.stress(x, t), s, 1e-12 * 1e8, x, t, "stress");
      check(bar.velocity(x, t), s / Z, 1e-12 * 1e8 / Z, x, t, "velocity");
    }
  }
  // Ramp part, two points: the slope in x is alpha / c.
  const double t = 1.5 / c;
  const double slope = (bar.stress(3.9, t) - bar.stress(3.0, t)) / 0.9;
  BOOST_TEST(std::abs(slope - alpha / c) <= 1e-9 * alpha / c);
  // Energy = work: integral of sigma_d * v(b) = sigma_d^2 / Z before any reflection comes back.
  const double te = 3.0 / c;
  const double work = (alpha * alpha * T1 * T1 * T1 / 3 + alpha * alpha * T1 * T1 * (te - T1)) / Z;
  BOOST_TEST(std::abs(bar.energy(te) - work) <= 1e-12 * work);
}

// Periodic bar: a pulse of w+ translates by c t, also after a thousand periods.
BOOST_AUTO_TEST_CASE(periodic_pulse_translates) {
  const double young = 4.0, rho = 1.0, c = 2.0, Z = 2.0, s = 3.0;
  const std::vector<Segment> init = {{0, 0.25, 0, 0}, {0.25, 0.5, s, -s / Z}, {0.5, 1, 0, 0}};
  const auto bar = ElasticBarSolution::periodic(0, 1, young, rho, init);
  for (double t : {0.0, 0.1, 0.3, 0.45, 1000.2}) {
    for (double x : points(0, 1, 101, 1e-4)) {
      double y = std::fmod(x - c * t, 1.0);
      if (y < 0) y += 1.0;
      const bool in = y > 0.25 && y < 0.5;
      if (std::abs(y - 0.25) < 1e-6 || std::abs(y - 0.5) < 1e-6) continue;
      check(bar.stress(x, t), in ? s : 0.0, 1e-9 * s, x, t, "stress");
      check(bar.velocity(x, t), in ? -s / Z : 0.0, 1e-9 * s, x, t, "velocity");
    }
    const double e0 = 0.25 * s * s / young;  // (w+^2) / (4 E) over the pulse, w+ = 2 s
    BOOST_TEST(std::abs(bar.energy(t) - e0) <= 1e-12 * e0, "energy at t = " << t);
  }
  BOOST_TEST(bar.is_periodic());
  // Both families, general data: energy conserved.
  const std::vector<Segment> gen = {
      {-1, -0.6, 2, 1}, {-0.6, 0.1, -1, 3}, {0.1, 0.35, 0.5, -2}, {0.35, 1.5, 0, 0.25}};
  const double e0 = segment_energy(gen, young, rho);
  const auto mixed = ElasticBarSolution::periodic(-1, 1.5, young, rho, gen);
  for (double t : {0.0, 0.1, 0.77, 3.3, 1000.123, 31415.9})
    BOOST_TEST(std::abs(mixed.energy(t) - e0) <= 1e-12 * e0, "energy at t = " << t);
}

// Energy conserved for free and fixed ends, general data, after many reflections.
BOOST_AUTO_TEST_CASE(energy_conserved_free_fixed) {
  const double L = 3.7;
  const std::vector<Segment> init = {{0, 0.3, 1e8, 5},  {0.3, 1.1, -2e8, -1}, {1.1, 1.15, 0, 7},
                                     {1.15, 2, 4e7, 0}, {2, 3.1, -5e7, 12},   {3.1, L, 2e8, -3}};
  const double e0 = segment_energy(init, steel_E, steel_rho);
  const double c = std::sqrt(steel_E / steel_rho);
  for (auto [l, r] : {std::pair{free_end(), free_end()}, std::pair{fixed_end(), fixed_end()},
                      std::pair{free_end(), fixed_end()}, std::pair{fixed_end(), free_end()}}) {
    const ElasticBarSolution bar(0, L, steel_E, steel_rho, init, l, r);
    for (double k : {0.0, 0.013, 0.3, 0.999, 1.0, 1.7, 2.0, 17.31, 1000.0, 1000.37, 12345.678})
      BOOST_TEST(std::abs(bar.energy(k * L / c) - e0) <= 1e-12 * e0, "energy at ct/L = " << k);
  }
  // The same with a traction end of zero value and a velocity end of zero value.
  const ElasticBarSolution zero(0, L, steel_E, steel_rho, init, end_of(BoundaryKind::traction, 0),
                                end_of(BoundaryKind::velocity, 0));
  for (double k : {0.4, 3.3, 1000.37})
    BOOST_TEST(std::abs(zero.energy(k * L / c) - e0) <= 1e-12 * e0, "energy at ct/L = " << k);
}

// Constant load against the opposite reflection sign (stress end with a fixed end, velocity end
// with a free end): the wave leaving the loaded end alternates between g and 0 at each round trip
// 2L/c, g = 2 sigma_d or 2 Z v_d. With W(tau) that wave at time tau, at (x, t):
// w- = W(t - (b - x)/c), w+ = +-W(t - (x - a)/c - L/c) (+ at a fixed end, - at a free end).
BOOST_AUTO_TEST_CASE(alternating_constant_loads) {
  const double L = 1.7, c = std::sqrt(steel_E / steel_rho), Z = steel_rho * c;
  const double sd = 3e8, vd = 1.5;
  const ElasticBarSolution trac(0, L, steel_E, steel_rho, {{0, L, 0, 0}}, fixed_end(),
                                end_of(BoundaryKind::traction, sd));
  const ElasticBarSolution vel(0, L, steel_E, steel_rho, {{0, L, 0, 0}}, free_end(),
                               end_of(BoundaryKind::velocity, vd));
  for (double k : {0.3, 1.2, 2.5, 3.7, 100.3, 101.4, 102.6, 103.9, 1000.05, 1001.55, 1002.95}) {
    const double t = k * L / c;
    for (double x : points(0, L, 23, 0.011)) {
      const auto W = [&](double tau, double g) {
        if (tau < 0) return 0.0;
        return std::fmod(std::floor(c * tau / (2 * L)), 2.0) == 0 ? g : 0.0;
      };
      const double tm = t - (L - x) / c, tp = t - x / c - L / c;
      const double wm_t = W(tm, 2 * sd), wp_t = W(tp, 2 * sd);
      check(trac.stress(x, t), 0.5 * (wp_t + wm_t), 1e-9 * sd, x, t, "stress, fixed/traction");
      check(trac.velocity(x, t), (wm_t - wp_t) / (2 * Z), 1e-9 * sd / Z, x, t,
            "velocity, fixed/traction");
      const double wm_v = W(tm, 2 * Z * vd), wp_v = -W(tp, 2 * Z * vd);
      check(vel.stress(x, t), 0.5 * (wp_v + wm_v), 1e-9 * Z * vd, x, t, "stress, free/velocity");
      check(vel.velocity(x, t), (wm_v - wp_v) / (2 * Z), 1e-9 * vd, x, t,
            "velocity, free/velocity");
    }
  }
}

// Balance laws over hundreds of crossings, both ends loaded (ramp then hold, and constant):
// d/dt int rho v dx = sigma(b) - sigma(a) with traction ends, d/dt int sigma dx = E (v(b) - v(a))
// with velocity ends.
BOOST_AUTO_TEST_CASE(balance_laws_long_time) {
  const double L = 1.3, c = std::sqrt(steel_E / steel_rho), Z = steel_rho * c, T1 = 0.7 * L / c;
  const std::vector<Segment> init = {{0, 0.4, 5e7, 3}, {0.4, L, -1e8, -2}};
  const double p0 = steel_rho * (0.4 * 3 - 0.9 * 2), s0 = 0.4 * 5e7 - 0.9 * 1e8;
  const auto midpoint = [&](const ElasticBarSolution& bar, double t, bool momentum) {
    const int n = 100000;
    double sum = 0;
    for (int i = 0; i < n; ++i) {
      const auto st = bar.state((i + 0.5) * L / n, t);
      sum += (momentum ? steel_rho * st.velocity : st.stress) * L / n;
    }
    return sum;
  };
  const double s1 = 2e8, s2 = -1.5e8;
  const ElasticBarSolution trac(0, L, steel_E, steel_rho, init,
                                table_end(BoundaryKind::traction, {0, T1}, {0, s1}),
                                end_of(BoundaryKind::traction, s2));
  const double v1 = 4, v2 = -2.5;
  const ElasticBarSolution vel(0, L, steel_E, steel_rho, init,
                               table_end(BoundaryKind::velocity, {0, T1}, {0, v1}),
                               end_of(BoundaryKind::velocity, v2));
  for (double k : {0.35, 3.3, 250.3, 1001.77}) {
    const double t = k * L / c;
    // Time integral of the ramp-then-hold of height h.
    const auto ramp = [&](double h) { return t < T1 ? h * t * t / (2 * T1) : h * (t - T1 / 2); };
    const double p = p0 + s2 * t - ramp(s1);
    BOOST_TEST(std::abs(midpoint(trac, t, true) - p) <= 1e-5 * (std::abs(p) + Z * 4),
               "momentum at ct/L = " << k << ": " << midpoint(trac, t, true) << " vs " << p);
    const double st = s0 + steel_E * (v2 * t - ramp(v1));
    BOOST_TEST(std::abs(midpoint(vel, t, false) - st) <= 1e-5 * (std::abs(st) + 1e8),
               "stress integral at ct/L = " << k << ": " << midpoint(vel, t, false) << " vs "
                                            << st);
  }
}

// energy() agrees with a fine midpoint sum of the pointwise fields.
BOOST_AUTO_TEST_CASE(energy_matches_pointwise_fields) {
  const double L = 2.0, c = std::sqrt(steel_E / steel_rho);
  const std::vector<Segment> init = {{0, 0.7, 1e8, 2}, {0.7, 1.3, -3e7, -4}, {1.3, L, 0, 1}};
  const ElasticBarSolution bar(0, L, steel_E, steel_rho, init, fixed_end(),
                               table_end(BoundaryKind::traction, {0, 1e-4}, {0, 2e8}));
  for (double t : {0.2 * L / c, 3.7 * L / c}) {
    const int n = 200000;
    double sum = 0;
    for (int i = 0; i < n; ++i) {
      const double x = (i + 0.5) * L / n;
      const auto st = bar.state(x, t);
      sum += (0.5 * steel_rho * st.velocity * st.velocity + st.stress * st.stress / (2 * steel_E)) *
             L / n;
    }
    BOOST_TEST(std::abs(bar.energy(t) - sum) <= 1e-4 * sum, "t = " << t);
  }
}

// Mirror x -> a + b - x, v -> -v, ends swapped (prescribed velocities negated): same stress,
// opposite velocity.
BOOST_AUTO_TEST_CASE(mirror_symmetry) {
  const double a = -1.0, b = 2.0, c = std::sqrt(steel_E / steel_rho);
  const std::vector<Segment> init = {{a, 0, 1e8, 3}, {0, 0.5, -2e8, -1}, {0.5, b, 4e7, 6}};
  std::vector<Segment> mirrored;
  for (const Segment& s : init) mirrored.push_back({a + b - s.x1, a + b - s.x0, s.sigma, -s.v});
  const auto left = table_end(BoundaryKind::traction, {0, 2e-4, 5e-4}, {0, 1e8, -5e7});
  const auto right = table_end(BoundaryKind::velocity, {1e-4, 3e-4}, {2, -1});
  const auto right_m = table_end(BoundaryKind::velocity, {1e-4, 3e-4}, {-2, 1});
  const ElasticBarSolution bar(a, b, steel_E, steel_rho, init, left, right);
  const ElasticBarSolution mir(a, b, steel_E, steel_rho, mirrored, right_m, left);
  for (double k : {0.1, 0.77, 1.5, 4.2, 31.9}) {
    const double t = k * (b - a) / c;
    for (int i = 0; i < 37; ++i) {
      const double x = a + (b - a) * (i + 0.37) / 37;  // off the fronts of both problems
      const auto p = bar.state(x, t), q = mir.state(a + b - x, t);
      const double scale = 1e-12 * (std::abs(p.stress) + 1e9);
      check(q.stress, p.stress, scale, x, t, "mirrored stress");
      check(q.velocity, -p.velocity, scale / (steel_rho * c), x, t, "mirrored velocity");
    }
    BOOST_TEST(std::abs(bar.energy(t) - mir.energy(t)) <= 1e-12 * bar.energy(t));
  }
}

// On a front the value is the limit from the right in x (from the left at x = b), including
// reflected fronts and fronts emitted at t = 0 from an end. c = 1 and dyadic data: exact fronts.
BOOST_AUTO_TEST_CASE(right_limit_at_fronts) {
  const std::vector<Segment> init = {{0, 1, 1, 0.5}, {1, 4, -2, 0}, {4, 6, 0.5, -1}, {6, 8, 0, 2}};
  const std::vector<std::pair<BoundaryCondition<1>, BoundaryCondition<1>>> ends = {
      {free_end(), fixed_end()},
      {end_of(BoundaryKind::traction, 1.5), end_of(BoundaryKind::velocity, -0.75)}};
  for (const auto& [l, r] : ends) {
    const ElasticBarSolution bar(0, 8, 1.0, 1.0, init, l, r);
    const double h = 1e-7;
    for (double t : {0.0, 1.0, 2.0, 3.0, 8.0, 9.5, 17.0}) {
      for (double x = 0; x <= 8; x += 0.5) {
        const double xs = x < 8 ? x + h : x - h;
        const auto p = bar.state(x, t), q = bar.state(xs, t);
        check(p.stress, q.stress, 1e-12, x, t, "one-sided stress");
        check(p.velocity, q.velocity, 1e-12, x, t, "one-sided velocity");
      }
    }
    // A front is really there: at t = 1 the jump at x = 4 has split into fronts at 3 and 5.
    BOOST_TEST(std::abs(bar.stress(3 - h, 1) - bar.stress(3 + h, 1)) > 0.1);
  }
  const auto per = ElasticBarSolution::periodic(0, 8, 1.0, 1.0, init);
  for (double t : {0.0, 1.0, 5.0, 100.5})
    for (double x = 0; x <= 8; x += 0.5) {
      const auto p = per.state(x, t), q = per.state(x < 8 ? x + 1e-7 : 1e-7, t);
      check(p.stress, q.stress, 1e-12, x, t, "periodic one-sided stress");
      check(p.velocity, q.velocity, 1e-12, x, t, "periodic one-sided velocity");
    }
}

BOOST_AUTO_TEST_CASE(bad_input_throws) {
  const std::vector<Segment> ok = {{0, 1, 0, 0}, {1, 2, 0, 1}};
  const auto make = [](double a, double b, double young, double rho, std::vector<Segment> s,
                       BoundaryCondition<1> l = free_end(), BoundaryCondition<1> r = free_end()) {
    return ElasticBarSolution(a, b, young, rho, std::move(s), l, r);
  };
  BOOST_CHECK_NO_THROW(make(0, 2, 1, 1, ok));
  BOOST_CHECK_NO_THROW(make(0, 2, 1, 1, {{1, 2, 0, 1}, {0, 1, 0, 0}}));  // any order
  BOOST_CHECK_THROW(make(2, 2, 1, 1, ok), std::invalid_argument);
  BOOST_CHECK_THROW(make(2, 0, 1, 1, ok), std::invalid_argument);
  BOOST_CHECK_THROW(make(0, NAN, 1, 1, ok), std::invalid_argument);
  BOOST_CHECK_THROW(make(0, 2, 0, 1, ok), std::invalid_argument);
  BOOST_CHECK_THROW(make(0, 2, -1, 1, ok), std::invalid_argument);
  BOOST_CHECK_THROW(make(0, 2, 1, 0, ok), std::invalid_argument);
  BOOST_CHECK_THROW(make(0, 2, 1, -3, ok), std::invalid_argument);
  BOOST_CHECK_THROW(make(0, 2, 1, 1, {}), std::invalid_argument);
  BOOST_CHECK_THROW(make(0, 2, 1, 1, {{0, 1, 0, 0}, {1.1, 2, 0, 0}}), std::invalid_argument);
  BOOST_CHECK_THROW(make(0, 2, 1, 1, {{0, 1.2, 0, 0}, {1, 2, 0, 0}}), std::invalid_argument);
  BOOST_CHECK_THROW(make(0, 2, 1, 1, {{0.1, 1, 0, 0}, {1, 2, 0, 0}}), std::invalid_argument);
  BOOST_CHECK_THROW(make(0, 2, 1, 1, {{0, 1, 0, 0}, {1, 1.9, 0, 0}}), std::invalid_argument);
  BOOST_CHECK_THROW(make(0, 2, 1, 1, {{0, 1, 0, 0}, {1, 1, 0, 0}, {1, 2, 0, 0}}),
                    std::invalid_argument);
  BOOST_CHECK_THROW(make(0, 2, 1, 1, {{0, 1, NAN, 0}, {1, 2, 0, 0}}), std::invalid_argument);
  BOOST_CHECK_THROW(make(0, 2, 1, 1, ok, BoundaryCondition<1>{BoundaryKind::traction, {}}),
                    std::invalid_argument);
  BOOST_CHECK_THROW(
      make(0, 2, 1, 1, ok, free_end(), table_end(BoundaryKind::velocity, {1, 0}, {0, 1})),
      std::invalid_argument);
  BOOST_CHECK_THROW(ElasticBarSolution::periodic(0, 2, 1, 1, {{0, 1, 0, 0}}),
                    std::invalid_argument);
  // Rounding-level mismatches are accepted.
  BOOST_CHECK_NO_THROW(make(0, 0.04 * 150, 1, 1, {{0, 3, 0, 0}, {3, 6, 0, 0}}));
  const auto bar = make(0, 2, 1, 1, ok);
  BOOST_CHECK_THROW(bar.state(-0.1, 0), std::out_of_range);
  BOOST_CHECK_THROW(bar.state(2.1, 0), std::out_of_range);
  BOOST_CHECK_THROW(bar.state(1, -1), std::out_of_range);
  BOOST_CHECK_THROW(bar.energy(NAN), std::out_of_range);
  BOOST_CHECK_NO_THROW(bar.state(2, 0));
}
