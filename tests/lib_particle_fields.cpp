// lib/: the particle fields described once (Particles::for_each_field) and the per-particle step
// after interpolation. Selection, records and the fields a step changes follow the one list; a
// physics with an internal variable, stepped by its particle step inside the fused sweep, leaves
// the states it shares with its elastic parent unchanged to the bit and counts every step.
#define BOOST_TEST_MODULE particle_fields
#include <boost/test/unit_test.hpp>

#include <dgmpm/physics/contract.hpp>
#include <dgmpm/physics/plane_strain.hpp>
#include <dgmpm/stepper.hpp>

#include "step_counting_plane.hpp"

#include <cmath>
#include <random>
#include <set>
#include <string>

using namespace dgmpm;

namespace {

// Plane strain with one internal variable, incremented by the particle step: a material with
// internal state that changes nothing else (the solver runs it in solver_new_material.cpp).
using CountingPlaneStrain = testing::StepCountingPlane;
static_assert(physics::ParticleStepPhysics<CountingPlaneStrain>);
static_assert(!physics::ParticleStepPhysics<PlaneStrain>);
static_assert(physics::DGPhysics<PlaneStrain> && physics::MpmConstitutive<PlaneStrain>);

using Set = Particles<2, 5, 3>;

Set random_set(int n, bool reference, std::mt19937& rng) {
  std::uniform_real_distribution<double> u(0, 1);
  Set p;
  p.tracks_reference = reference;
  p.resize(n);
  for (int i = 0; i < n; ++i)
    p.for_each_field([&](const FieldInfo& info, auto& field) {
      if (p.columns(info, 1) == 0) return;
      std::vector<double> v(static_cast<std::size_t>(particle_field::width(field)));
      for (double& x : v) x = std::floor(1000 * u(rng));  // exact in the int fields too
      particle_field::read(field, i, v.data());
    });
  return p;
}

// Every field of particle i of a equals that of particle j of b.
bool same_particle(const Set& a, int i, const Set& b, int j) {
  bool same = true;
  Set::for_each_field_of(
      [&](const FieldInfo& info, const auto& x, const auto& y) {
        if (a.columns(info, 1) == 0) return;
        std::vector<double> u(8), v(8);
        particle_field::write(x, i, u.data());
        particle_field::write(y, j, v.data());
        same = same && u == v;
      },
      a, b);
  return same;
}

}  // namespace

BOOST_AUTO_TEST_CASE(the_list_names_each_field_once_with_its_width) {
  Set p;
  p.tracks_reference = true;
  p.resize(4);
  std::set<std::string> names;
  int width = 0;
  p.for_each_field([&](const FieldInfo& info, const auto& field) {
    names.insert(info.name);
    width += particle_field::width(field);
  });
  BOOST_TEST(names.size() == 8u);
  // position 2, mass, volume, state 5, internal 3, material, id, reference 2
  BOOST_TEST(width == 2 + 1 + 1 + 5 + 3 + 1 + 1 + 2);
  BOOST_TEST(p.record_width() == width);
  BOOST_TEST(p.stepped_width() == 5 + 3);
  p.tracks_reference = false;
  BOOST_TEST(p.record_width() == width - 2);
}

BOOST_AUTO_TEST_CASE(selection_and_records_carry_every_field) {
  std::mt19937 rng(3);
  for (bool reference : {false, true}) {
    const Set p = random_set(7, reference, rng);
    const std::vector<int> order{6, 0, 3, 3};
    const Set q = p.select(order);
    BOOST_TEST(q.size() == 4);
    BOOST_TEST(q.reference.cols() == (reference ? 4 : 0));
    for (int i = 0; i < q.size(); ++i) BOOST_TEST(same_particle(q, i, p, order[i]));
    // Records, as MPI sends them: written and read back, the same particle.
    std::vector<double> record;
    for (int i = 0; i < p.size(); ++i) p.write_record(i, record);
    BOOST_TEST(static_cast<int>(record.size()) == p.size() * p.record_width());
    Set r;
    r.tracks_reference = reference;
    r.resize(p.size());
    for (int i = 0; i < p.size(); ++i)
      r.read_record(p.size() - 1 - i, record.data() + i * p.record_width());
    for (int i = 0; i < p.size(); ++i) BOOST_TEST(same_particle(r, p.size() - 1 - i, p, i));
    // The record's position is where the MPI code reads it.
    for (int a = 0; a < 2; ++a) BOOST_TEST(record[Set::record_position + a] == p.position(a, 0));
    // A step's fields: state and internal variables, nothing else.
    std::vector<double> stepped(p.stepped_width());
    p.write_stepped(2, stepped.data());
    for (int k = 0; k < 5; ++k) BOOST_TEST(stepped[k] == p.state(k, 2));
    for (int k = 0; k < 3; ++k) BOOST_TEST(stepped[5 + k] == p.internal(k, 2));
    Set s = r;
    s.read_stepped(0, stepped.data());
    BOOST_TEST((s.state.col(0) == p.state.col(2)));
    BOOST_TEST((s.internal.col(0) == p.internal.col(2)));
    BOOST_TEST(s.mass[0] == r.mass[0]);
  }
}

BOOST_AUTO_TEST_CASE(resizing_keeps_what_it_is_asked_to) {
  std::mt19937 rng(5);
  const Set p = random_set(3, true, rng);
  Set q = p;
  q.resize(5, true);
  BOOST_TEST(q.size() == 5);
  BOOST_TEST(q.reference.cols() == 5);
  BOOST_TEST(q.internal.cols() == 5);
  for (int i = 0; i < 3; ++i) BOOST_TEST(same_particle(q, i, p, i));
}

// A 12 x 10 plate with a free and a loaded side and two particles per cell (neither centred):
// the counting material's particle step runs inside every integrator's last sweep, once per
// particle and step, and changes no state.
BOOST_AUTO_TEST_CASE(the_particle_step_runs_once_per_particle_and_step_and_changes_nothing_else) {
  for (const TimeScheme time : {TimeScheme::euler, TimeScheme::rk2})
    for (const FluxScheme flux : {FluxScheme::dcu, FluxScheme::ctu}) {
      Grid<2> grid;
      grid.cells = {12, 10};
      grid.cell_size = {1.0, 0.8};
      Boundaries<2> boundaries{};
      boundaries[0][0] =
          BoundaryCondition<2>{BoundaryKind::traction, TimeTable<2>::constant({-1e-3, 2e-4})};
      const PlaneStrain::Material steel(200.0, 0.3, 7.8);
      std::vector<PlaneStrain::Material> materials{steel};
      ParticlesOf<PlaneStrain> elastic;
      ParticlesOf<CountingPlaneStrain> counting;
      std::mt19937 rng(11);
      std::uniform_real_distribution<double> u(0.05, 0.95), s(-1e-3, 1e-3);
      const int n = 2 * 12 * 10;
      elastic.resize(n);
      for (int p = 0; p < n; ++p) {
        const int c = p / 2;
        elastic.position(0, p) = (c % 12 + u(rng)) * 1.0;
        elastic.position(1, p) = (c / 12 + u(rng)) * 0.8;
        elastic.volume[p] = 0.4;
        elastic.mass[p] = 0.4 * steel.density;
        for (int k = 0; k < 5; ++k) elastic.state(k, p) = s(rng);
        elastic.material[p] = 0;
        elastic.id[p] = p;
      }
      counting.resize(n);
      Particles<2, 5>::for_each_field_of(
          [](const FieldInfo&, auto& to, const auto& from) {
            if constexpr (std::is_same_v<std::remove_cvref_t<decltype(to)>,
                                         std::remove_cvref_t<decltype(from)>>)
              to = from;  // all but the internal variables, which the elastic set has none of
          },
          counting, elastic);
      counting.internal.setZero();
      const StepperOptions options{time, flux};
      Stepper<PlaneStrain> a(grid, boundaries, options);
      Stepper<CountingPlaneStrain> b(grid, boundaries, options);
      a.rebuild(elastic, materials);
      b.rebuild(counting, materials);
      const Eigen::MatrixXd initial = elastic.state;
      const int steps = 25;
      const double dt = 0.3 * 0.8 / steel.p_speed();
      for (int k = 0; k < steps; ++k) {
        BOOST_TEST(a.step(elastic, materials, k * dt, dt));
        BOOST_TEST(b.step(counting, materials, k * dt, dt));
      }
      BOOST_TEST((elastic.state - counting.state).cwiseAbs().maxCoeff() == 0.0);
      BOOST_TEST((elastic.state - initial).cwiseAbs().maxCoeff() > 1e-4);  // waves did run
      BOOST_TEST(counting.internal.minCoeff() == steps);
      BOOST_TEST(counting.internal.maxCoeff() == steps);
    }
}
