// Steps are fused: one pass over the cells per stage projects each cell (a few layers of cells
// ahead), computes CTU's faces (a layer ahead), each cell's whole residual and update (and, for
// Euler and RK2's last stage, its particles). The unfused definition is the composition of four
// stages over whole arrays, project -> residual (volume terms, then face by face) -> update ->
// interpolate, written out here from the operator's per-cell and per-face parts, for Euler and
// Heun's RK2: both must give the same particle states, on 1D and 2D scenes with boundaries
// (traction, free, roller), periodic axes, void cells, massless and near-empty nodes, over-full
// and empty cells inside a body, and two materials, with DCU and CTU fluxes.
#define BOOST_TEST_MODULE solver_fused_steps
#include <boost/test/unit_test.hpp>

#include "common/loaded_scenes.hpp"
#include "solver/problem.hpp"
#include "solver/scene.hpp"
#include "solver/simulation.hpp"

#include <nlohmann/json.hpp>

#include <string>

using namespace dgmpm;
using nlohmann::json;

namespace {

json bar(const std::string& integrator) {
  return test::loaded_bar(70, 0.1, integrator, false);
}

json plate(const std::string& integrator, const std::string& flux = "dcu") {
  return test::loaded_plate(20, 14, 0.25, 2, flux, integrator, false);
}

// Moves particles so that some nodes are massless (a particle on its cell's lower node along
// every axis), some cells inside the body over-full and others empty.
template <int Dim, int NComp>
void disturb(Particles<Dim, NComp>& p, const Grid<Dim>& grid) {
  for (int k = 0; k < p.size(); k += 7) {
    Eigen::Matrix<double, Dim, 1> xi;
    const int c = grid.locate(p.position.col(k), xi);
    const auto index = grid.unflatten(c);
    for (int a = 0; a < Dim; ++a) p.position(a, k) = grid.origin[a] + index[a] * grid.cell_size[a];
  }
  for (int k = 3; k < p.size(); k += 11) p.position(0, k) += grid.cell_size[0];
}

// The unfused stages, each over a whole array.
template <class Physics>
struct Unfused {
  using Op = DGOperator<Physics>;
  using NodalField = typename Op::NodalField;
  using ParticleField = typename Op::ParticleField;
  using State = typename Physics::State;
  static constexpr int dim = Physics::dim, npc = Op::npc;
  const Op& op;
  const typename Op::Disc& disc;
  FluxScheme flux;

  void project(const ParticleField& qp, const Eigen::VectorXd& mass, NodalField& q) const {
    q.setZero(Physics::n_comp, op.num_nodes());
    for (int c = 0; c < disc.num_cells(); ++c)
      for (int e = disc.cell_begin(c); e < disc.cell_end(c); ++e) {
        const int p = disc.entry_particle(e);
        q.template middleCols<npc>(c * npc) +=
            mass[p] * qp.col(p) * disc.entry_shape(e).transpose();
      }
    for (int i = 0; i < op.num_nodes(); ++i)
      if (disc.node_source(i) == i) q.col(i) *= disc.inverse_mass(i);
    copy_massless(q);
  }

  // Volume terms cell by cell, then every face's flux scattered to its two cells' face nodes.
  void residual(const NodalField& q, const Eigen::VectorXd& mass, double t, double dt,
                NodalField& r) const {
    r.setZero(Physics::n_comp, op.num_nodes());
    for (int c = 0; c < disc.num_cells(); ++c) {
      if (!disc.occupied(c)) continue;
      typename Op::CellBlock rc = Op::CellBlock::Zero();
      op.add_volume_term(c, q.template middleCols<npc>(c * npc), mass, rc);
      r.template middleCols<npc>(c * npc) = rc;
    }
    std::array<NodalField, dim> star;
    typename Op::FaceFluctuations w;
    std::array<std::vector<char>, dim> active;
    for (int l = 0; l < dim; ++l) {
      star[l].setZero(Physics::n_comp, op.num_faces(l));
      w[l].setZero(Physics::n_comp, 2 * op.num_faces(l));
      active[l].assign(op.num_faces(l), 0);
      for (int f = 0; f < op.num_faces(l); ++f) {
        State s = State::Zero();
        active[l][f] = op.face_star(l, f, q, t, s);
        star[l].col(f) = s;
        const auto [cm, cp] = op.face_cells(l, f);
        if constexpr (dim > 1)
          for (int side = 0; side < 2; ++side) {
            const int c = side ? cp : cm;
            if (flux == FluxScheme::ctu && c >= 0 && disc.occupied(c))
              w[l].col(2 * f + side) = op.entering_fluctuation(l, f, s, q, dt, side);
          }
      }
    }
    for (int l = 0; l < dim; ++l)
      for (int f = 0; f < op.num_faces(l); ++f) {
        if (!active[l][f]) continue;
        State s = star[l].col(f);
        if constexpr (dim > 1)
          if (flux == FluxScheme::ctu) s += op.transverse_correction(l, f, w);
        const auto [cm, cp] = op.face_cells(l, f);
        for (int side = 0; side < 2; ++side) {
          const int c = side ? cp : cm;
          if (c < 0 || !disc.occupied(c)) continue;
          // The minus cell's upper nodes lose w F_l(q*), the plus cell's lower nodes gain it.
          const State fl = op.face_weight(l) * Physics::flux(l, s, disc.cell_material(c));
          for (int a = 0; a < npc; ++a)
            if (((a >> l) & 1) == !side) r.col(c * npc + a) += side ? fl : State(-fl);
        }
      }
  }

  // q += dt M^-1 r, a massless node's residual moved to the node standing in for it.
  void update(NodalField& q, NodalField r, double dt) const {
    for (int i = 0; i < op.num_nodes(); ++i) {
      const int s = disc.node_source(i);
      if (s >= 0 && s != i) r.col(s) += r.col(i);
    }
    for (int i = 0; i < op.num_nodes(); ++i)
      if (disc.node_source(i) >= 0) q.col(i) += (dt * disc.inverse_mass(i)) * r.col(i);
    copy_massless(q);
  }

  void interpolate(const NodalField& q, ParticleField& qp) const {
    for (int c = 0; c < disc.num_cells(); ++c)
      for (int e = disc.cell_begin(c); e < disc.cell_end(c); ++e)
        qp.col(disc.entry_particle(e)) = q.template middleCols<npc>(c * npc) * disc.entry_shape(e);
  }

  void copy_massless(NodalField& q) const {
    for (int i = 0; i < op.num_nodes(); ++i) {
      const int s = disc.node_source(i);
      if (s >= 0 && s != i) q.col(i) = q.col(s);
    }
  }
};

template <class Physics>
double largest_difference(const json& doc, int steps) {
  const scene::Scene scene = scene::parse_scene(doc, "fused");
  Problem<Physics> problem = make_problem<Physics>(scene);
  disturb(problem.particles, problem.grid);
  const StepperOptions options = stepper_options(scene);
  Stepper<Physics> stepper(problem.grid, problem.boundaries, options);
  stepper.rebuild(problem.particles, problem.materials);
  const auto& op = stepper.op();
  const auto& disc = stepper.discretisation();
  BOOST_TEST_REQUIRE(disc.has_massless_nodes());
  BOOST_TEST_REQUIRE(disc.has_near_empty_nodes());  // RK2 damps their first stage
  int empty = 0;
  for (int c = 0; c < disc.num_cells(); ++c) empty += !disc.occupied(c);
  BOOST_TEST_REQUIRE(empty > 0);

  const Eigen::VectorXd& mass = problem.particles.mass;
  const double dt = 0.4 * problem.grid.cell_size.minCoeff() / problem.max_wave_speed();
  using Op = DGOperator<Physics>;
  typename Op::ParticleField fused = problem.particles.state, unfused = fused;
  typename Op::NodalField q0, q1, r;
  const Unfused<Physics> reference{op, disc, options.flux};
  double worst = 0.0, scale = 0.0;
  for (int n = 0; n < steps; ++n) {
    const double t = n * dt;
    stepper.step(fused, mass, t, dt);
    reference.project(unfused, mass, q0);
    reference.residual(q0, mass, t, dt, r);
    if (options.time == TimeScheme::euler) {
      reference.update(q0, r, dt);
      reference.interpolate(q0, unfused);
    } else {
      // Heun, its second residual at the damped first stage qd = q0 + w (q1 - q0) (w: a node's
      // share of its cell's mass over the stage share, at most 1; massless nodes keep their copy)
      // and what damping took away added back: (q0 + qd + dt M^-1 r(qd) + (q1 - qd)) / 2.
      q1 = q0;
      reference.update(q1, r, dt);
      typename Op::NodalField qd = q1;
      for (int i = 0; i < op.num_nodes(); ++i) {
        const int c = i / Op::npc;
        if (!disc.occupied(c) || disc.node_source(i) != i) continue;
        const double share = disc.node_mass(i) / disc.cell_mass(c);
        const double w = std::min(1.0, share / Discretisation<Physics>::stage_share);
        qd.col(i) = q0.col(i) + w * (q1.col(i) - q0.col(i));
      }
      typename Op::NodalField q2 = qd;
      reference.residual(qd, mass, t + dt, dt, r);
      reference.update(q2, r, dt);
      q0 = 0.5 * (q0 + q2 + (q1 - qd));
      reference.interpolate(q0, unfused);
    }
    worst = std::max(worst, (fused - unfused).cwiseAbs().maxCoeff());
    scale = std::max(scale, unfused.cwiseAbs().maxCoeff());
  }
  BOOST_TEST_REQUIRE(fused.allFinite());
  BOOST_TEST_REQUIRE(scale > 0.0);
  return worst / scale;
}

}  // namespace

BOOST_AUTO_TEST_CASE(fused_steps_equal_the_composition_of_the_stages) {
  for (const std::string integrator : {"euler", "rk2"}) {
    BOOST_TEST_CONTEXT(integrator) {
      const double bar_difference = largest_difference<ElasticBar>(bar(integrator), 40);
      const double plate_difference = largest_difference<PlaneStrain>(plate(integrator), 20);
      BOOST_TEST_MESSAGE(integrator << ": largest relative difference, 1D " << bar_difference
                                    << ", 2D " << plate_difference);
      BOOST_TEST(bar_difference <= 1e-14);
      BOOST_TEST(plate_difference <= 1e-14);
      const double ring =
          largest_difference<ElasticBar>(test::periodic(bar(integrator), {true}), 40);
      const double torus = largest_difference<PlaneStrain>(
          test::periodic(test::filled(plate(integrator)), {true, true}), 20);
      const double tube =
          largest_difference<PlaneStrain>(test::periodic(plate(integrator), {true, false}), 20);
      BOOST_TEST_MESSAGE(integrator << ": periodic 1D " << ring << ", 2D " << torus
                                    << ", 2D periodic along x " << tube);
      BOOST_TEST(ring <= 1e-14);
      BOOST_TEST(torus <= 1e-14);
      BOOST_TEST(tube <= 1e-14);
      const double ctu = largest_difference<PlaneStrain>(plate(integrator, "ctu"), 20);
      const double ctu_torus = largest_difference<PlaneStrain>(
          test::periodic(test::filled(plate(integrator, "ctu")), {true, true}), 20);
      const double ctu_tube = largest_difference<PlaneStrain>(
          test::periodic(plate(integrator, "ctu"), {true, false}), 20);
      BOOST_TEST_MESSAGE(integrator << ": CTU " << ctu << ", periodic " << ctu_torus
                                    << ", periodic along x " << ctu_tube);
      BOOST_TEST(ctu <= 1e-14);
      BOOST_TEST(ctu_torus <= 1e-14);
      BOOST_TEST(ctu_tube <= 1e-14);
    }
  }
}
