// lib/: 1D finite strain (total Lagrangian, uniaxial strain), Saint Venant-Kirchhoff and
// neo-Hookean, stepped by lib's Stepper. The laws against their closed forms and finite
// differences; the exact solutions of the half-space loaded at its end, computed here from the
// jump and fan relations of the equations (bisection, not the code's law evaluation order) and
// checked against the published values (docs/method.md, "Finite strain"): the SVK tension shocks
// (2 and 20 GPa; plateau means of F - 1, P and v within 1e-3, shock within two cells), the
// compression fan (-20 GPa; L1 error of F falling with the cell size), the neo-Hookean impact at
// +-100 m/s; at a small load, the plateaus against small strain by the laws' leading terms;
// energy never above the initial energy plus the work of the load; a compression past SVK's
// hyperbolic range stops the steps.
#define BOOST_TEST_MODULE finite_strain
#include <boost/test/unit_test.hpp>

#include "common/hyperelastic.hpp"

#include <dgmpm/physics/contract.hpp>
#include <dgmpm/physics/elastic_bar.hpp>
#include <dgmpm/physics/finite_strain_bar.hpp>
#include <dgmpm/stepper.hpp>

#include <cmath>
#include <functional>
#include <memory>
#include <vector>

using namespace dgmpm;
using SVK = FiniteStrainBar<SaintVenantKirchhoff>;
using NH = FiniteStrainBar<NeoHookean>;

static_assert(physics::DGPhysics<SVK> && physics::DGPhysics<NH>);
static_assert(physics::DirectBoundary<SVK> && !physics::GhostBoundary<SVK>);
static_assert(physics::HasEnergy<SVK>);

namespace {

constexpr double E = test::kYoung, nu = test::kPoisson, rho0 = test::kRho0;
const double lambda = test::kLambda, mu = test::kMu, M = test::kM, kappa = test::kKappa;
using test::bisect, test::nh_energy, test::svk_stress;

// A half-space X >= 0 (a bar of `length`, long enough that no wave reaches its far end) at rest
// and unstrained, one particle per cell, under a nominal stress `load` at X = 0.
template <class P>
struct HalfSpace {
  using Physics = P;
  Grid<1> grid;
  ParticlesOf<P> particles;
  std::vector<typename P::Material> materials{typename P::Material(E, nu, rho0)};
  Boundaries<1> boundaries{};
  HalfSpace(int cells, double length, double load) {
    grid.cells = {cells};
    const double h = length / cells;
    grid.cell_size = Eigen::Matrix<double, 1, 1>(h);
    particles.resize(cells);
    for (int p = 0; p < cells; ++p) {
      particles.position(0, p) = (p + 0.5) * h;
      particles.volume[p] = h;
      particles.mass[p] = rho0 * h;
      particles.state.col(p) = P::specific(1.0, 0.0, materials[0]);
      particles.internal.col(p).setZero();  // the displacement
      particles.material[p] = 0;
      particles.id[p] = p;
    }
    boundaries[0][0] = BoundaryCondition<1>{
        BoundaryKind::traction, TimeTable<1>::constant(Eigen::Matrix<double, 1, 1>(load))};
  }
  double energy() const {
    double e = 0;
    for (int p = 0; p < particles.size(); ++p)
      e += particles.mass[p] * P::energy_per_mass(particles.state.col(p), materials[0]);
    return e;
  }
  double max_speed() const {
    double c = 0;
    for (int p = 0; p < particles.size(); ++p)
      c = std::max(c, P::wave_speed(particles.state(0, p) * rho0, materials[0]));
    return c;
  }
};

struct Run {
  std::vector<double> x, f, v;
  double time = 0, worst_excess = 0;  // largest (E - E0 - W) / W over the steps
};

// Steps until t_end at Courant number C from the particles' current speeds (Euler or RK2, DCU).
template <class P>
Run run(HalfSpace<P>& s, TimeScheme scheme, double courant, double t_end) {
  Stepper<P> stepper(s.grid, s.boundaries, StepperOptions{scheme});
  stepper.rebuild(s.particles, s.materials);
  Run r;
  const double e0 = s.energy(), h = s.grid.cell_size[0];
  double work = 0;
  while (r.time < t_end) {
    const double dt = std::min(courant * h / s.max_speed(), t_end - r.time);
    const double power0 = stepper.op().boundary_power(s.particles.state, s.particles.mass, r.time);
    BOOST_REQUIRE(stepper.step(s.particles, s.materials, r.time, dt));
    if (scheme == TimeScheme::euler) {
      work += dt * power0;
    } else {  // Heun: the load's power at both stages' states (the second's: its particles')
      work +=
          0.5 * dt *
          (power0 + stepper.op().boundary_power(s.particles.state, s.particles.mass, r.time + dt));
    }
    r.time += dt;
    r.worst_excess = std::max(r.worst_excess, (s.energy() - e0 - work) / std::abs(work));
  }
  for (int p = 0; p < s.particles.size(); ++p) {
    r.x.push_back(s.particles.position(0, p));
    r.f.push_back(s.particles.state(0, p) * rho0);
    r.v.push_back(s.particles.state(1, p));
  }
  return r;
}

// Means of F, P and v over X in [a, b].
struct Plateau {
  double f = 0, p = 0, v = 0;
};
template <class P>
Plateau mean_over(const Run& r, double a, double b, const typename P::Material& m) {
  Plateau m_;
  int n = 0;
  for (std::size_t i = 0; i < r.x.size(); ++i) {
    if (r.x[i] < a || r.x[i] > b) continue;
    m_.f += r.f[i];
    m_.p += P::nominal_stress(r.f[i], m);
    m_.v += r.v[i];
    ++n;
  }
  BOOST_REQUIRE(n > 20);
  return {m_.f / n, m_.p / n, m_.v / n};
}

}  // namespace

BOOST_AUTO_TEST_CASE(the_laws_are_their_closed_forms_and_their_own_derivatives) {
  const SVK::Material svk(E, nu, rho0);
  const NH::Material nh(E, nu, rho0);
  for (double f : {0.7, 0.9, 0.99, 1.0, 1.01, 1.1, 1.5}) {
    BOOST_TEST(SVK::nominal_stress(f, svk) == svk_stress(f), boost::test_tools::tolerance(1e-14));
    const double d = 1e-6;
    for (const auto& [stress, tangent, energy] :
         {std::tuple{+[](double g) { return SVK::nominal_stress(g, SVK::Material(E, nu, rho0)); },
                     +[](double g) { return SVK::tangent(g, SVK::Material(E, nu, rho0)); },
                     +[](double g) { return SVK::strain_energy(g, SVK::Material(E, nu, rho0)); }},
          std::tuple{+[](double g) { return NH::nominal_stress(g, NH::Material(E, nu, rho0)); },
                     +[](double g) { return NH::tangent(g, NH::Material(E, nu, rho0)); },
                     +[](double g) { return NH::strain_energy(g, NH::Material(E, nu, rho0)); }}}) {
      // P = dW/dF and dP/dF by central differences, to 1e-7 of the modulus M (truncation d^2,
      // round-off 1e-16 / d)
      BOOST_TEST(std::abs(stress(f) - (energy(f + d) - energy(f - d)) / (2 * d)) <= 1e-7 * M);
      BOOST_TEST(std::abs(tangent(f) - (stress(f + d) - stress(f - d)) / (2 * d)) <= 1e-7 * M);
    }
    BOOST_TEST(NH::strain_energy(f, nh) == nh_energy(f), boost::test_tools::tolerance(1e-12));
  }
  // Both are small-strain elasticity at F = 1: P = 0, dP/dF = lambda + 2 mu, W = 0.
  BOOST_TEST(SVK::tangent(1.0, svk) == M, boost::test_tools::tolerance(1e-15));
  BOOST_TEST(NH::tangent(1.0, nh) == M, boost::test_tools::tolerance(1e-15));
  BOOST_TEST(NH::nominal_stress(1.0, nh) == 0.0);
  // SVK loses hyperbolicity at F = 1/sqrt(3): the wave speed is NaN past it.
  BOOST_TEST(std::abs(SVK::tangent(1 / std::sqrt(3.0), svk)) <= 1e-15 * M);
  BOOST_TEST(std::isnan(SVK::wave_speed(0.5, svk)));
}

// The 3D laws of F = diag(a, b, c), written here: the uniaxial nominal stress is dW/da and the
// lateral Cauchy stress (dW/db) b / J at (f, 1, 1), by central differences; the Cauchy tensor and
// F the outputs write are diag(P, sigma_yy, sigma_yy) and diag(f, 1, 1).
BOOST_AUTO_TEST_CASE(the_lateral_cauchy_stress_is_the_3d_laws_derivative) {
  const auto svk_3d = [](double a, double b, double c) {
    const double e[3] = {0.5 * (a * a - 1), 0.5 * (b * b - 1), 0.5 * (c * c - 1)};
    const double tr = e[0] + e[1] + e[2];
    return 0.5 * lambda * tr * tr + mu * (e[0] * e[0] + e[1] * e[1] + e[2] * e[2]);
  };
  const auto nh_3d = [](double a, double b, double c) {
    const double j = a * b * c;
    return 0.5 * mu * (std::pow(j, -2.0 / 3.0) * (a * a + b * b + c * c) - 3) +
           0.5 * kappa * (j - 1) * (j - 1);
  };
  const double d = 1e-6;
  for (double f : {0.7, 0.95, 1.0, 1.05, 1.3}) {
    const auto check = [&](auto physics, const auto& w) {
      using P = decltype(physics);
      const typename P::Material m(E, nu, rho0);
      const double p_xx = (w(f + d, 1, 1) - w(f - d, 1, 1)) / (2 * d);
      const double sigma_yy = (w(f, 1 + d, 1) - w(f, 1 - d, 1)) / (2 * d) / f;
      const typename P::State s(f, 0.0);  // physical (F, v)
      const Eigen::Matrix<double, 1, 1> z(0.0);
      const auto derived = P::derived(s, z, m);
      BOOST_TEST(std::abs(derived[0] - p_xx) <= 1e-7 * M);
      BOOST_TEST(std::abs(derived[1] - sigma_yy) <= 1e-7 * M);
      BOOST_TEST(derived[2] == f);  // J
      const Eigen::Matrix3d sigma = P::cauchy_stress_tensor(s, z, m);
      BOOST_TEST(sigma(0, 0) == derived[0]);
      BOOST_TEST(sigma(1, 1) == derived[1]);
      BOOST_TEST(sigma(2, 2) == derived[1]);
      BOOST_TEST((sigma - Eigen::Matrix3d(sigma.diagonal().asDiagonal())).norm() == 0.0);
      BOOST_CHECK(P::deformation_gradient_tensor(s, z) ==
                  Eigen::Matrix3d(Eigen::Vector3d(f, 1, 1).asDiagonal()));
    };
    check(SVK{}, svk_3d);
    check(NH{}, nh_3d);
  }
}

// The displacement follows the velocity after the step: u += dt v.
BOOST_AUTO_TEST_CASE(the_particle_step_carries_the_displacement) {
  const SVK::Material m(E, nu, rho0);
  SVK::State q = SVK::specific(1.01, -3.5, m);
  Eigen::Matrix<double, 1, 1> z(0.25);
  SVK::particle_step(q, z, m, 2e-3);
  BOOST_TEST(z[0] == 0.25 - 3.5 * 2e-3);
  BOOST_TEST(SVK::displacement_of(z)[0] == z[0]);
  BOOST_CHECK(q == SVK::specific(1.01, -3.5, m));  // the state itself is left alone
}

// At a small jump the linearised star state is small-strain elasticity's, and a boundary star
// prescribes what it should (traction: P*; velocity: v*; free: P* = 0).
BOOST_AUTO_TEST_CASE(star_states_are_the_linear_ones_near_the_reference_and_meet_their_conditions) {
  const SVK::Material m(E, nu, rho0);
  const double z = std::sqrt(rho0 * M), e = 1e-9;
  const SVK::State minus = SVK::specific(1 + e, 0.3, m), plus = SVK::specific(1 - e, -0.1, m);
  const SVK::State star = SVK::riemann(0, minus, m, plus, m);
  // Small strain: sigma = M eps on each side.
  const double sm = M * e, sp = -M * e;
  BOOST_TEST(star[1] == (z * 0.3 + z * -0.1 + sp - sm) / (2 * z),
             boost::test_tools::tolerance(1e-6));
  BOOST_TEST(star[0] == (sm + sp + z * (-0.1 - 0.3)) / 2, boost::test_tools::tolerance(1e-6));
  const SVK::State q = SVK::specific(1.01, 5.0, m);
  for (int side = 0; side < 2; ++side) {
    const auto value = Eigen::Matrix<double, 1, 1>(3e8);
    BOOST_TEST(SVK::boundary_star(BoundaryKind::traction, value, 0, q, m, side)[0] == 3e8);
    BOOST_TEST(SVK::boundary_star(BoundaryKind::velocity, value, 0, q, m, side)[1] == 3e8);
    BOOST_TEST(SVK::boundary_star(BoundaryKind::free, value, 0, q, m, side)[0] == 0.0);
    BOOST_TEST(SVK::boundary_star(BoundaryKind::fixed, value, 0, q, m, side)[1] == 0.0);
    // The boundary star is the Riemann problem's against a mirror state of equal impedance: a
    // traction equal to the inside's stress and the inside's velocity leaves the state as it is.
    const double p = SVK::nominal_stress(1.01, m);
    const SVK::State same =
        SVK::boundary_star(BoundaryKind::traction, Eigen::Matrix<double, 1, 1>(p), 0, q, m, side);
    BOOST_TEST(same[1] == 5.0, boost::test_tools::tolerance(1e-12));
  }
}

// SVK tension at the end X = 0 pulling toward -X: a shock; behind it F > 1, v < 0.
BOOST_AUTO_TEST_CASE(svk_tension_shocks_reach_the_exact_plateaus) {
  const SVK::Material m(E, nu, rho0);
  struct Case {
    double load, f, s, v;  // the published shock (docs/method.md)
  };
  for (const Case c : {Case{2e9, 1.007347, 5907.5, -43.40}, Case{20e9, 1.067333, 6171.0, -415.5}}) {
    // Exact: P(F) = load, s^2 = P / (rho0 (F - 1)) (Rankine-Hugoniot), v = -s (F - 1).
    const double f = bisect([&](double g) { return svk_stress(g) - c.load; }, 1.0, 1.5);
    const double s = std::sqrt(c.load / (rho0 * (f - 1))), v = -s * (f - 1);
    BOOST_TEST(f == c.f, boost::test_tools::tolerance(1e-6));
    BOOST_TEST(s == c.s, boost::test_tools::tolerance(2e-5));
    BOOST_TEST(v == c.v, boost::test_tools::tolerance(2e-4));
    for (const TimeScheme scheme : {TimeScheme::euler, TimeScheme::rk2}) {
      BOOST_TEST_CONTEXT("load " << c.load << ", " << to_string(scheme)) {
        const int cells = 1200;
        const double length = 3.0, t_end = 3.5e-4, h = length / cells;
        HalfSpace<SVK> half(cells, length, c.load);
        const Run r = run(half, scheme, 0.9, t_end);
        const double front = s * r.time;
        const Plateau mean = mean_over<SVK>(r, 0.2 * front, 0.8 * front, m);
        BOOST_TEST_MESSAGE("plateau F - 1 " << mean.f - 1 << " (exact " << f - 1 << "), P "
                                            << mean.p << ", v " << mean.v << " (exact " << v
                                            << "); energy excess " << r.worst_excess);
        BOOST_TEST(mean.f - 1 == f - 1, boost::test_tools::tolerance(1e-3));
        BOOST_TEST(mean.p == c.load, boost::test_tools::tolerance(1e-3));
        BOOST_TEST(mean.v == v, boost::test_tools::tolerance(1e-3));
        // The shock: where F - 1 crosses half its jump.
        double crossing = 0;
        for (std::size_t i = 0; i + 1 < r.x.size(); ++i)
          if (r.f[i] - 1 >= 0.5 * (f - 1) && r.f[i + 1] - 1 < 0.5 * (f - 1)) crossing = r.x[i];
        BOOST_TEST(std::abs(crossing - front) <= 2 * h,
                   "shock at " << crossing << ", exact " << front);
        BOOST_TEST(r.worst_excess <= 1e-9);
      }
    }
  }
}

// SVK compression: a rarefaction fan from F = 1 (head at c(1)) to the loaded state (tail at
// c(F_tail)), F(xi) = sqrt((1 + 2 rho0 xi^2 / M) / 3) inside; the L1 error of F falls with h.
BOOST_AUTO_TEST_CASE(svk_compression_opens_the_exact_fan) {
  const double load = -20e9;
  const double f_tail = bisect([&](double g) { return svk_stress(g) - load; }, 0.6, 1.0);
  const double head = std::sqrt(M / rho0),
               tail = std::sqrt(M * (3 * f_tail * f_tail - 1) / (2 * rho0));
  BOOST_TEST(f_tail == 0.915243, boost::test_tools::tolerance(1e-6));
  BOOST_TEST(head == 5875.0, boost::test_tools::tolerance(2e-4));
  BOOST_TEST(tail == 5110.0, boost::test_tools::tolerance(2e-4));
  const auto exact = [&](double x, double t) {
    const double xi = x / t;
    if (xi >= head) return 1.0;
    if (xi <= tail) return f_tail;
    return std::sqrt((1 + 2 * rho0 * xi * xi / M) / 3);
  };
  std::vector<double> errors;
  for (const int cells : {300, 1200}) {
    const double length = 3.0, t_end = 3.5e-4;
    HalfSpace<SVK> half(cells, length, load);
    const Run r = run(half, TimeScheme::euler, 0.9, t_end);
    double error = 0;
    for (std::size_t i = 0; i < r.x.size(); ++i)
      error += std::abs(r.f[i] - exact(r.x[i], r.time)) * (length / cells);
    errors.push_back(error);
    BOOST_TEST(r.worst_excess <= 1e-9);
    // Behind the tail the material moves toward +X.
    const Plateau mean =
        mean_over<SVK>(r, 0.1 * tail * r.time, 0.8 * tail * r.time, SVK::Material(E, nu, rho0));
    BOOST_TEST(mean.f == f_tail, boost::test_tools::tolerance(1e-4));
    BOOST_TEST(mean.v > 0);
  }
  const double order = std::log(errors[0] / errors[1]) / std::log(4.0);
  BOOST_TEST_MESSAGE("fan: L1 error of F " << errors[0] << " at 300 cells, " << errors[1]
                                           << " at 1200; order " << order);
  BOOST_TEST(order > 0.5);
}

// Neo-Hookean halves at +-100 m/s meeting at X = 3: two shocks, F*, P* and the shock speed from
// the jump relations: s (F* - 1) = -100, P* = -rho0 s 100.
BOOST_AUTO_TEST_CASE(neo_hookean_halves_meeting_reach_the_exact_shocked_state) {
  const NH::Material m(E, nu, rho0);
  const double v0 = 100;
  const double f_star = bisect(
      [&](double g) { return NH::nominal_stress(g, m) + v0 * v0 * rho0 / (1 - g); }, 0.9, 0.9999);
  const double s = v0 / (1 - f_star), p_star = -rho0 * s * v0;
  BOOST_TEST(f_star == 0.983044, boost::test_tools::tolerance(1e-6));
  BOOST_TEST(p_star == -4.600e9, boost::test_tools::tolerance(1e-4));
  BOOST_TEST(s == 5897.6, boost::test_tools::tolerance(2e-5));
  const int cells = 1200;
  const double length = 6.0, t_end = 2e-4;
  HalfSpace<NH> bar(cells, length, 0.0);
  bar.boundaries[0][0] = BoundaryCondition<1>{};  // free ends
  for (int p = 0; p < cells; ++p)
    bar.particles.state(1, p) = bar.particles.position(0, p) < 0.5 * length ? v0 : -v0;
  const Run r = run(bar, TimeScheme::euler, 0.9, t_end);
  const double reach = s * r.time;
  const Plateau mean = mean_over<NH>(r, 0.5 * length - 0.7 * reach, 0.5 * length + 0.7 * reach, m);
  BOOST_TEST_MESSAGE("neo-Hookean: F* " << mean.f << " (exact " << f_star << "), P* " << mean.p);
  BOOST_TEST(mean.f - 1 == f_star - 1, boost::test_tools::tolerance(1e-3));
  BOOST_TEST(mean.p == p_star, boost::test_tools::tolerance(1e-3));
  BOOST_TEST(std::abs(mean.v) < 1e-6 * v0);
  BOOST_TEST(r.worst_excess <= 1e-9);
}

// At a small load (P_d = 1e6 Pa, strain eps = P_d / M = 3.7e-6) the plateaus differ from
// small-strain elasticity's (the elastic bar with modulus M, stepped the same way) by the laws'
// leading terms: SVK's F - 1 = eps - 1.5 eps^2 (P = M (e + 1.5 e^2 + ...)), neo-Hookean's
// F - 1 = eps + (14 mu / 9 M) eps^2 = eps + 0.444 eps^2 at nu = 0.3.
BOOST_AUTO_TEST_CASE(small_loads_differ_from_small_strain_by_the_leading_terms) {
  const double load = 1e6, eps = load / M, length = 3.0, t_end = 3.5e-4;
  const int cells = 600;
  const double h = length / cells;
  // The small-strain plateau: the elastic bar, same grid, particles, load and steps.
  Grid<1> grid;
  grid.cells = {cells};
  grid.cell_size = Eigen::Matrix<double, 1, 1>(h);
  ParticlesOf<ElasticBar> bar;
  bar.resize(cells);
  std::vector<ElasticBar::Material> elastic{ElasticBar::Material(M, rho0)};
  for (int p = 0; p < cells; ++p) {
    bar.position(0, p) = (p + 0.5) * h;
    bar.volume[p] = h;
    bar.mass[p] = rho0 * h;
    bar.state.col(p) << 0.0, 0.0;
    bar.material[p] = 0;
    bar.id[p] = p;
  }
  Boundaries<1> boundaries{};
  boundaries[0][0] = BoundaryCondition<1>{
      BoundaryKind::traction, TimeTable<1>::constant(Eigen::Matrix<double, 1, 1>(load))};
  Stepper<ElasticBar> stepper(grid, boundaries, StepperOptions{});
  stepper.rebuild(bar, elastic);
  const double c = std::sqrt(M / rho0), dt = 0.9 * h / c;
  double t = 0;
  while (t < t_end) {
    BOOST_REQUIRE(stepper.step(bar, elastic, t, dt));
    t += dt;
  }
  const auto small_strain_plateau = [&] {
    double sum = 0;
    int n = 0;
    for (int p = 0; p < cells; ++p)
      if (bar.position(0, p) > 0.2 * c * t && bar.position(0, p) < 0.8 * c * t) {
        sum += bar.state(0, p) * rho0 / M;
        ++n;
      }
    return sum / n;
  }();
  BOOST_TEST(small_strain_plateau == eps, boost::test_tools::tolerance(1e-9));
  // The finite-strain plateaus, at the elastic bar's time step (the speeds differ by 1e-5).
  const auto plateau = [&](auto half) {
    Stepper<typename decltype(half)::element_type::Physics> s(half->grid, half->boundaries,
                                                              StepperOptions{});
    s.rebuild(half->particles, half->materials);
    double time = 0;
    while (time < t_end) {
      BOOST_REQUIRE(s.step(half->particles, half->materials, time, dt));
      time += dt;
    }
    double sum = 0;
    int n = 0;
    for (int p = 0; p < cells; ++p)
      if (half->particles.position(0, p) > 0.2 * c * time &&
          half->particles.position(0, p) < 0.8 * c * time) {
        sum += half->particles.state(0, p) * rho0 - 1;
        ++n;
      }
    return sum / n;
  };
  const double svk = plateau(std::make_shared<HalfSpace<SVK>>(cells, length, load));
  const double nh = plateau(std::make_shared<HalfSpace<NH>>(cells, length, load));
  const double svk_term = (svk - small_strain_plateau) / (eps * eps);
  const double nh_term = (nh - small_strain_plateau) / (eps * eps);
  BOOST_TEST_MESSAGE("small load: (F - 1 - eps) / eps^2 = " << svk_term << " (SVK), " << nh_term
                                                            << " (neo-Hookean)");
  BOOST_TEST(svk_term == -1.5, boost::test_tools::tolerance(0.005));
  BOOST_TEST(nh_term == 14 * mu / (9 * M), boost::test_tools::tolerance(0.005));
}

// SVK's nominal stress in compression is smallest at F = 1/sqrt(3), -M / (3 sqrt(3)) = -5.18e10 Pa:
// a load beyond it drives F past the loss of hyperbolicity, where the tangent impedance is NaN,
// and the step says so (it returns false: the solver stops there) rather than going on.
BOOST_AUTO_TEST_CASE(a_compression_past_svk_hyperbolic_range_stops_the_steps) {
  const double weakest = -M / (3 * std::sqrt(3.0));
  BOOST_TEST(SVK::nominal_stress(1 / std::sqrt(3.0), SVK::Material(E, nu, rho0)) == weakest,
             boost::test_tools::tolerance(1e-12));
  HalfSpace<SVK> half(300, 3.0, 1.2 * weakest);
  Stepper<SVK> stepper(half.grid, half.boundaries, StepperOptions{});
  stepper.rebuild(half.particles, half.materials);
  const double dt = 0.5 * 0.01 / std::sqrt(M / rho0);
  int steps = 0;
  bool finite = true;
  while (finite && steps < 1000)
    finite = stepper.step(half.particles, half.materials, steps++ * dt, dt);
  BOOST_TEST(!finite);
  BOOST_TEST_MESSAGE("a load of 1.2 times SVK's weakest compression: non-finite at step " << steps);
  // And a load just within it runs: F stays above 1/sqrt(3).
  HalfSpace<SVK> within(300, 3.0, 0.9 * weakest);
  Stepper<SVK> second(within.grid, within.boundaries, StepperOptions{});
  second.rebuild(within.particles, within.materials);
  for (int s = 0; s < 200; ++s)
    BOOST_REQUIRE(second.step(within.particles, within.materials, s * dt, dt));
  BOOST_TEST(within.particles.state.row(0).minCoeff() * rho0 > 1 / std::sqrt(3.0));
}
