// The volume term's products with the pseudo-stiffness, sum_l F_l K^l^T, are summed particle by
// particle without forming K^l in 2D cells of one particle
// (Discretisation::add_stiffness_products), and there, for a linear flux, from the flux of the
// state at the particle. The sums must equal the products with the matrices stiffness() forms, to
// round-off: 1D and 2D, one to three particles per cell at random places and masses (part-full
// and over-full cells, whose consistency correction is not zero), both formulations, random
// fluxes and states.
#define BOOST_TEST_MODULE volume_term
#include <boost/test/unit_test.hpp>

#include <dgmpm/dg_operator.hpp>
#include <dgmpm/discretisation.hpp>
#include <dgmpm/physics/elastic_bar.hpp>
#include <dgmpm/physics/elastoplastic_bar.hpp>
#include <dgmpm/physics/finite_strain_bar.hpp>
#include <dgmpm/physics/finite_strain_plane.hpp>
#include <dgmpm/physics/plane_strain.hpp>
#include <dgmpm/physics/plane_strain_plastic.hpp>

#include <array>
#include <cmath>
#include <random>
#include <vector>

using namespace dgmpm;

namespace {

template <class Physics>
void compare(Formulation formulation, std::mt19937& rng) {
  constexpr int dim = Physics::dim, npc = 1 << dim, ncomp = Physics::n_comp;
  Grid<dim> grid;
  for (int l = 0; l < dim; ++l) {
    grid.cell_size[l] = 0.5 / (l + 1);
    grid.cells[l] = 5;
  }
  const std::vector<typename Physics::Material> materials(1);
  std::uniform_real_distribution<double> u(0.02, 0.98);
  Particles<dim, ncomp> p;
  p.resize(3 * grid.num_cells());
  int n = 0;
  for (int c = 0; c < grid.num_cells(); ++c) {
    const auto k = grid.unflatten(c);
    for (int q = 0; q < 1 + c % 3; ++q, ++n) {
      for (int l = 0; l < dim; ++l) p.position(l, n) = (k[l] + u(rng)) * grid.cell_size[l];
      p.mass[n] = (0.2 + u(rng)) * Physics::density(materials[0]) * grid.cell_volume();
      p.volume[n] = 1.0;
      p.material[n] = 0;
      p.id[n] = n;
    }
  }
  p.resize(n, true);
  Discretisation<Physics> disc;
  disc.set_formulation(formulation);
  disc.build(grid, p, materials);
  int corrected = 0;
  for (int c = 0; c < grid.num_cells(); ++c) {
    std::array<Eigen::Matrix<double, ncomp, npc>, dim> flux;
    for (auto& f : flux) f = Eigen::Matrix<double, ncomp, npc>::Random();
    const auto k = disc.stiffness(c, p.mass);
    Eigen::Matrix<double, ncomp, npc> formed = Eigen::Matrix<double, ncomp, npc>::Zero();
    Eigen::Matrix<double, ncomp, npc> summed = Eigen::Matrix<double, ncomp, npc>::Zero();
    for (int l = 0; l < dim; ++l) formed += flux[l] * k[l].transpose();
    disc.add_stiffness_products(
        c, p.mass,
        [&](const auto& w) {
          std::array<Eigen::Matrix<double, ncomp, 1>, dim> f;
          for (int l = 0; l < dim; ++l) f[l] = flux[l] * w;
          return f;
        },
        summed);
    BOOST_TEST((summed - formed).cwiseAbs().maxCoeff() <= 1e-13 * formed.cwiseAbs().maxCoeff(),
               "cell " << c << " of " << disc.cell_end(c) - disc.cell_begin(c) << " particles");
    // Without the correction the row sums of K^l are the cell's own; with it, the exact ones.
    Eigen::Matrix<double, npc, 1> rows = k[0].rowwise().sum();
    const double exact = disc.cell_mass(c) / disc.fill(c) / (grid.cell_size[0] * (npc / 2));
    corrected +=
        std::abs(std::abs(rows[0]) - exact) < 1e-12 * exact && std::abs(disc.fill(c) - 1.0) > 0.05;
  }
  if (formulation == Formulation::consistent) BOOST_TEST(corrected > 0);
}

}  // namespace

BOOST_AUTO_TEST_CASE(products_without_forming_the_stiffness_equal_those_with_it) {
  std::mt19937 rng(7);
  for (const Formulation f : {Formulation::consistent, Formulation::paper}) {
    compare<ElasticBar>(f, rng);
    compare<PlaneStrain>(f, rng);
  }
}

// A physics declaring its flux linear (physics::LinearFlux) has F(a q1 + b q2) = a F(q1) + b F(q2)
// along each axis, for random states and a material of distinct moduli; finite strain does not
// declare it.
template <class Physics>
void check_linear(const typename Physics::Material& m, std::mt19937& rng) {
  static_assert(physics::LinearFlux<Physics>);
  std::uniform_real_distribution<double> u(-1.0, 1.0);
  using State = typename Physics::State;
  for (int trial = 0; trial < 20; ++trial) {
    State q1, q2;
    for (int k = 0; k < Physics::n_comp; ++k) {
      q1[k] = u(rng) * 1e3;
      q2[k] = u(rng) * 1e3;
    }
    const double a = u(rng), b = u(rng);
    for (int l = 0; l < Physics::dim; ++l) {
      const State whole = Physics::specific_flux(l, a * q1 + b * q2, m);
      const State parts =
          a * Physics::specific_flux(l, q1, m) + b * Physics::specific_flux(l, q2, m);
      BOOST_TEST((whole - parts).cwiseAbs().maxCoeff() <= 1e-13 * parts.cwiseAbs().maxCoeff());
    }
  }
}

BOOST_AUTO_TEST_CASE(fluxes_declared_linear_are_linear) {
  std::mt19937 rng(3);
  check_linear<ElasticBar>({2e11, 7800}, rng);
  check_linear<ElastoPlasticBar>(ElastoPlasticBar::Material(2e11, 7800), rng);
  check_linear<PlaneStrain>({2e11, 0.3, 7800}, rng);
  check_linear<PlaneStrainPlastic>(PlaneStrainPlastic::Material(2e11, 0.3, 7800), rng);
  BOOST_TEST(!physics::LinearFlux<FiniteStrainPlane<NeoHookean>>);
  BOOST_TEST(!physics::LinearFlux<FiniteStrainBar<NeoHookean>>);
}

// The operator's volume term of 2D cells of one particle (rank-one sums of the state's flux at the
// particle, physics::LinearFlux) equals the products of the nodes' fluxes with the K^l that
// stiffness() forms, to round-off: random nodal states, particles at random places (no two cells
// share a layout) and on a lattice (every cell shares one), both formulations.
BOOST_AUTO_TEST_CASE(volume_term_from_the_flux_at_the_particle_equals_the_formed_products) {
  constexpr int npc = 4, ncomp = PlaneStrain::n_comp;
  std::mt19937 rng(11);
  std::uniform_real_distribution<double> u(0.02, 0.98);
  Grid<2> grid;
  grid.cell_size << 0.5, 0.25;
  grid.cells = {5, 4};
  const std::vector<PlaneStrain::Material> materials{{2e11, 0.3, 7800}};
  const Boundaries<2> boundaries{};
  int compared = 0;
  for (const bool lattice : {false, true})
    for (const Formulation f : {Formulation::consistent, Formulation::paper}) {
      Particles<2, ncomp> p;
      p.resize(grid.num_cells());
      for (int c = 0; c < grid.num_cells(); ++c) {
        const auto k = grid.unflatten(c);
        for (int l = 0; l < 2; ++l)
          p.position(l, c) = (k[l] + (lattice ? 0.5 : u(rng))) * grid.cell_size[l];
        p.mass[c] = (lattice ? 1.0 : 0.2 + u(rng)) * 7800 * grid.cell_volume();
        p.volume[c] = 1.0;
        p.material[c] = 0;
        p.id[c] = c;
      }
      Discretisation<PlaneStrain> disc;
      disc.set_formulation(f);
      disc.build(grid, p, materials);
      BOOST_TEST_REQUIRE((disc.shared_cells() == grid.num_cells()) == lattice);
      const DGOperator<PlaneStrain> op(grid, disc, boundaries);
      for (int c = 0; c < grid.num_cells(); ++c) {
        const Eigen::Matrix<double, ncomp, npc> q =
            1e3 * Eigen::Matrix<double, ncomp, npc>::Random();
        const auto k = disc.stiffness(c, p.mass);
        Eigen::Matrix<double, ncomp, npc> formed = Eigen::Matrix<double, ncomp, npc>::Zero();
        for (int l = 0; l < 2; ++l) {
          Eigen::Matrix<double, ncomp, npc> flux;
          for (int a = 0; a < npc; ++a)
            flux.col(a) = PlaneStrain::specific_flux(l, q.col(a), materials[0]);
          formed += flux * k[l].transpose();
        }
        Eigen::Matrix<double, ncomp, npc> summed = Eigen::Matrix<double, ncomp, npc>::Zero();
        op.add_volume_term(c, q, p.mass, summed);
        BOOST_TEST((summed - formed).cwiseAbs().maxCoeff() <= 1e-13 * formed.cwiseAbs().maxCoeff(),
                   "cell " << c);
        ++compared;
      }
    }
  BOOST_TEST(compared == 4 * 20);
}

// The plate cases of `bench --json` rely on these: in 2D a cell of one particle sums its products
// particle by particle and cells of more form K; in 1D cells form K.
BOOST_AUTO_TEST_CASE(which_cells_sum_without_forming_the_stiffness) {
  BOOST_TEST(Discretisation<PlaneStrain>::rank_one_cheaper(1));
  BOOST_TEST(!Discretisation<PlaneStrain>::rank_one_cheaper(2));
  BOOST_TEST(!Discretisation<PlaneStrain>::rank_one_cheaper(4));
  BOOST_TEST(!Discretisation<ElasticBar>::rank_one_cheaper(1));
}
