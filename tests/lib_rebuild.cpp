// The discretisation's rebuild is incremental: when no particle changed cell since the last
// build, the cells keep their particle lists (no sort) and only the values are recomputed. It
// must give what a build from scratch gives, value for value; the first over-full cell it reports
// must be the one a pass over the cells finds. On threads (large grids) a build gives what one
// thread gives, blends of mixed cells included.
#define BOOST_TEST_MODULE rebuild
#include <boost/test/unit_test.hpp>

#include <dgmpm/discretisation.hpp>
#include <dgmpm/physics/plane_strain.hpp>

#include <algorithm>
#include <omp.h>
#include <random>
#include <vector>

using namespace dgmpm;

namespace {

using Disc = Discretisation<PlaneStrain>;
using ParticleSet = Particles<2, PlaneStrain::n_comp>;

Grid<2> grid(int nx = 8, int ny = 6) {
  Grid<2> g;
  g.cell_size << 0.5, 0.25;
  g.cells = {nx, ny};
  return g;
}

// Two particles in most cells (none in a few), random positions inside their cells, two
// materials (by cell, or with `mixed` drawn per particle), each cell's two masses summing to
// between 0.5 and 1.5 times a full cell's.
ParticleSet particles(const Grid<2>& g, const std::vector<PlaneStrain::Material>& materials,
                      std::mt19937& rng, bool mixed = false) {
  std::uniform_real_distribution<double> u(0.05, 0.95);
  ParticleSet p;
  p.resize(2 * g.num_cells());
  int n = 0;
  for (int c = 0; c < g.num_cells(); ++c) {
    if (c % 7 == 3) continue;
    const auto k = g.unflatten(c);
    for (int q = 0; q < 2; ++q, ++n) {
      for (int a = 0; a < 2; ++a) p.position(a, n) = (k[a] + u(rng)) * g.cell_size[a];
      const int m = mixed ? (u(rng) < 0.5) : c % 2;
      p.mass[n] = (0.5 + u(rng)) * 0.5 * materials[m].density * g.cell_volume();
      p.volume[n] = 1.0;
      p.material[n] = m;
      p.id[n] = n;
    }
  }
  ParticleSet used;
  used.resize(n);
  used.position = p.position.leftCols(n);
  used.mass = p.mass.head(n);
  used.volume = p.volume.head(n);
  used.material.assign(p.material.begin(), p.material.begin() + n);
  used.id.assign(p.id.begin(), p.id.begin() + n);
  return used;
}

void same(const Disc& a, const Disc& b, const Grid<2>& g, const Eigen::VectorXd& mass) {
  BOOST_TEST_REQUIRE(a.num_cells() == b.num_cells());
  for (int c = 0; c < g.num_cells(); ++c) {
    BOOST_TEST_REQUIRE(a.cell_begin(c) == b.cell_begin(c));
    BOOST_TEST_REQUIRE(a.cell_end(c) == b.cell_end(c));
    BOOST_TEST(a.occupied(c) == b.occupied(c));
    for (int e = a.cell_begin(c); e < a.cell_end(c); ++e) {
      BOOST_TEST(a.entry_particle(e) == b.entry_particle(e));
      BOOST_TEST((a.entry_shape(e) == b.entry_shape(e)));
    }
    for (int l = 0; l < 2; ++l) BOOST_TEST((a.stiffness(c, mass)[l] == b.stiffness(c, mass)[l]));
    BOOST_TEST(a.cell_material(c).lambda() == b.cell_material(c).lambda());
  }
  for (int i = 0; i < g.num_nodes(); ++i) {
    BOOST_TEST(a.node_mass(i) == b.node_mass(i));
    BOOST_TEST(a.inverse_mass(i) == b.inverse_mass(i));
    BOOST_TEST(a.node_source(i) == b.node_source(i));
  }
  BOOST_TEST(a.first_overfull_cell() == b.first_overfull_cell());
}

}  // namespace

BOOST_AUTO_TEST_CASE(incremental_rebuild_equals_a_build_from_scratch) {
  std::mt19937 rng(3);
  const Grid<2> g = grid();
  const std::vector<PlaneStrain::Material> materials{{2e11, 0.3, 7800}, {2e10, 0.25, 2000}};
  ParticleSet p = particles(g, materials, rng);
  Disc kept;
  kept.build(g, p, materials);
  BOOST_TEST(kept.sorts() == 1);
  // Moves inside the cells: no sort, the values of a fresh build.
  std::uniform_real_distribution<double> nudge(-0.02, 0.02);
  for (int step = 0; step < 3; ++step) {
    for (int n = 0; n < p.size(); ++n) {
      Eigen::Matrix<double, 2, 1> xi = Eigen::Matrix<double, 2, 1>::Zero();
      const int c = g.locate(p.position.col(n), xi);
      for (int a = 0; a < 2; ++a)
        p.position(a, n) +=
            std::clamp(nudge(rng), -0.9 * xi[a], 0.9 * (1 - xi[a])) * g.cell_size[a];
      BOOST_TEST_REQUIRE(g.locate(p.position.col(n), xi) == c);
    }
    kept.build(g, p, materials);
    Disc fresh;
    fresh.build(g, p, materials);
    same(kept, fresh, g, p.mass);
  }
  BOOST_TEST(kept.sorts() == 1);
  // One particle into the next cell: sorted again, still a fresh build's values (an over-full
  // cell among them).
  p.position(0, 0) += g.cell_size[0];
  kept.build(g, p, materials);
  BOOST_TEST(kept.sorts() == 2);
  Disc fresh;
  fresh.build(g, p, materials);
  same(kept, fresh, g, p.mass);
  // The first over-full cell, found by a pass over the cells (there is one: about half the
  // cells' masses exceed a full cell's).
  int first = -1;
  for (int c = 0; c < g.num_cells() && first < 0; ++c)
    if (kept.occupied(c) &&
        kept.cell_mass(c) / (kept.cell_material(c).density * g.cell_volume()) > 1 + 1e-6)
      first = c;
  BOOST_TEST_REQUIRE(first >= 0);
  BOOST_TEST(kept.first_overfull_cell() == first);
}

BOOST_AUTO_TEST_CASE(a_threaded_build_equals_a_one_thread_build) {
  std::mt19937 rng(5);
  const Grid<2> g = grid(80, 60);
  BOOST_TEST_REQUIRE(g.num_cells() >= Disc::kThreaded);
  const std::vector<PlaneStrain::Material> materials{{2e11, 0.3, 7800}, {2e10, 0.25, 2000}};
  const ParticleSet p = particles(g, materials, rng, true);
  Disc one, two;
  omp_set_num_threads(1);
  one.build(g, p, materials);
  omp_set_num_threads(2);
  BOOST_TEST_REQUIRE(omp_get_max_threads() == 2);
  two.build(g, p, materials);
  int mixed = 0;
  for (int c = 0; c < g.num_cells(); ++c) {
    if (!one.occupied(c)) continue;
    int steel = 0, cell = 0;
    for (int e = one.cell_begin(c); e < one.cell_end(c); ++e, ++cell)
      steel += p.material[one.entry_particle(e)] == 0;
    mixed += steel > 0 && steel < cell;
  }
  BOOST_TEST(mixed > 1000);
  BOOST_TEST(one.first_overfull_cell() >= 0);
  same(one, two, g, p.mass);
}

// The sort by cell on threads: particles in no order (each cell's drawn from anywhere in the
// arrays), each thread counting and placing a range of them, give the one-thread build's cell
// lists, each in increasing particle order.
BOOST_AUTO_TEST_CASE(a_threaded_sort_gives_the_one_thread_order) {
  std::mt19937 rng(11);
  const Grid<2> g = grid(80, 60);
  const std::vector<PlaneStrain::Material> materials{{2e11, 0.3, 7800}, {2e10, 0.25, 2000}};
  const ParticleSet ordered = particles(g, materials, rng, true);
  std::vector<int> order(ordered.size());
  for (int n = 0; n < ordered.size(); ++n) order[n] = n;
  std::shuffle(order.begin(), order.end(), rng);
  ParticleSet p;
  p.resize(ordered.size());
  for (int n = 0; n < p.size(); ++n) {
    p.position.col(n) = ordered.position.col(order[n]);
    p.mass[n] = ordered.mass[order[n]];
    p.volume[n] = ordered.volume[order[n]];
    p.material[n] = ordered.material[order[n]];
    p.id[n] = n;
  }
  BOOST_TEST_REQUIRE(p.size() >= Disc::kThreaded);  // the threaded build
  Disc one, two;
  omp_set_num_threads(1);
  one.build(g, p, materials);
  omp_set_num_threads(2);
  two.build(g, p, materials);
  BOOST_TEST(one.sorts() == 1);
  BOOST_TEST(two.sorts() == 1);
  int increasing = 0, pairs = 0, shared = 0;
  for (int c = 0; c < g.num_cells(); ++c) {
    for (int e = two.cell_begin(c) + 1; e < two.cell_end(c); ++e, ++pairs) {
      increasing += two.entry_particle(e) > two.entry_particle(e - 1);
      // a cell whose particles came from both halves of the arrays: both threads placed them
      shared += two.entry_particle(e - 1) < p.size() / 2 && two.entry_particle(e) >= p.size() / 2;
    }
  }
  BOOST_TEST(pairs > 1000);
  BOOST_TEST(increasing == pairs);
  BOOST_TEST(shared > 1000);
  same(one, two, g, p.mass);
}
