// The volume term's products with the pseudo-stiffness, sum_l F_l K^l^T, are summed particle by
// particle without forming K^l in 2D cells of one particle
// (Discretisation::add_stiffness_products). The sums must equal the products with the matrices
// stiffness() forms, to round-off: 1D and 2D, one to three particles per cell at random places
// and masses (part-full and over-full cells, whose consistency correction is not zero), both
// formulations, random fluxes.
#define BOOST_TEST_MODULE volume_term
#include <boost/test/unit_test.hpp>

#include <dgmpm/discretisation.hpp>
#include <dgmpm/physics/elastic_bar.hpp>
#include <dgmpm/physics/plane_strain.hpp>

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
    disc.add_stiffness_products(c, p.mass, flux, summed);
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

// The plate cases of `bench --json` rely on these: in 2D a cell of one particle sums its products
// particle by particle and cells of more form K; in 1D cells form K.
BOOST_AUTO_TEST_CASE(which_cells_sum_without_forming_the_stiffness) {
  BOOST_TEST(Discretisation<PlaneStrain>::rank_one_cheaper(1));
  BOOST_TEST(!Discretisation<PlaneStrain>::rank_one_cheaper(2));
  BOOST_TEST(!Discretisation<PlaneStrain>::rank_one_cheaper(4));
  BOOST_TEST(!Discretisation<ElasticBar>::rank_one_cheaper(1));
}
