// Run under mpirun (2 and 4 ranks): the block decomposition numbers the ranks, places them and
// finds their face neighbours as MPI's Cartesian topology does (MPI_Cart_coords, MPI_Cart_rank,
// MPI_Cart_shift, periodic axes included), and the ranks' blocks add up to the grid.
#define BOOST_TEST_MODULE distributed_cartesian_ranks
#include <boost/test/unit_test.hpp>

#include "cartesian_ranks.hpp"
#include "common/grids.hpp"
#include "common/mpi_session.hpp"

#include <mpi.h>

#include <stdexcept>

using namespace dgmpm;
using test::grid;

namespace {

template <int D>
void agrees_with_mpi(const Grid<D>& g) {
  const distributed::CartesianRanks<D> ranks(MPI_COMM_WORLD, g);
  const auto& b = ranks.blocks();
  int size = 0;
  MPI_Comm_size(ranks.comm(), &size);
  BOOST_TEST_REQUIRE(b.num_ranks() == size);
  for (int r = 0; r < size; ++r) {
    int coords[D];
    MPI_Cart_coords(ranks.comm(), r, D, coords);
    const auto k = b.coords(r);
    for (int l = 0; l < D; ++l) BOOST_TEST(coords[l] == k[l]);
    int mpi_rank = -1;
    MPI_Cart_rank(ranks.comm(), coords, &mpi_rank);
    BOOST_TEST(mpi_rank == r);
  }
  for (int l = 0; l < D; ++l) {
    int below = 0, above = 0;
    MPI_Cart_shift(ranks.comm(), l, 1, &below, &above);
    typename BlockDecomposition<D>::Index up{}, down{};
    up[l] = 1;
    down[l] = -1;
    const auto ours = [](int n) { return n < 0 ? MPI_PROC_NULL : n; };
    BOOST_TEST(ours(b.neighbour(ranks.rank(), down)) == below);
    BOOST_TEST(ours(b.neighbour(ranks.rank(), up)) == above);
  }
  // Each cell owned once: the owners' counts add up over the ranks to the grid's cells.
  int mine = 0;
  for (int c = 0; c < g.num_cells(); ++c) mine += b.owner(g.unflatten(c)) == ranks.rank();
  BOOST_TEST(mine == b.owned_cells(ranks.rank()));
  int total = 0;
  MPI_Allreduce(&mine, &total, 1, MPI_INT, MPI_SUM, ranks.comm());
  BOOST_TEST(total == g.num_cells());
}

}  // namespace

BOOST_AUTO_TEST_CASE(layouts_agree_with_mpi_topologies) {
  for (bool p : {false, true}) agrees_with_mpi<1>(grid<1>({12}, {p}));
  for (bool px : {false, true})
    for (bool py : {false, true}) agrees_with_mpi<2>(grid<2>({10, 7}, {px, py}));
  agrees_with_mpi<3>(grid<3>({5, 4, 6}, {true, false, true}));
}

BOOST_AUTO_TEST_CASE(more_ranks_than_cells_is_refused_on_every_rank) {
  int size = 0;
  MPI_Comm_size(MPI_COMM_WORLD, &size);
  BOOST_TEST_REQUIRE(size > 1);  // run under mpirun -np 2 or more
  BOOST_CHECK_THROW(distributed::CartesianRanks<1>(MPI_COMM_WORLD, grid<1>({1}, {false})),
                    std::invalid_argument);
}
