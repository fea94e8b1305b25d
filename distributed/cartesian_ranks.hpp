#pragma once
// The ranks of an MPI communicator laid out over a grid: MPI_Dims_create chooses how many ranks
// go along each axis, MPI_Cart_create makes the topology (periodic where the grid is), and the
// block decomposition says which cells each rank owns (lib/dgmpm/decomposition.hpp; both number
// the ranks the same way, tests/distributed_cartesian_ranks.cpp checks it against MPI).

#include <dgmpm/decomposition.hpp>

#include <mpi.h>

namespace dgmpm::distributed {

template <int Dim>
class CartesianRanks {
 public:
  // Collective over `world`. Throws std::invalid_argument (on every rank) when MPI's layout puts
  // more ranks along an axis than the grid has cells.
  CartesianRanks(MPI_Comm world, const Grid<Dim>& grid) {
    int size = 1;
    MPI_Comm_size(world, &size);
    int dims[Dim] = {}, periods[Dim] = {};
    MPI_Dims_create(size, Dim, dims);
    typename BlockDecomposition<Dim>::Index layout{};
    for (int l = 0; l < Dim; ++l) {
      layout[l] = dims[l];
      periods[l] = grid.periodic[l] ? 1 : 0;
    }
    blocks_ = BlockDecomposition<Dim>(grid, layout);  // before any communicator exists
    // No reordering: rank r of `world` is rank r here, the block decomposition's numbering.
    MPI_Cart_create(world, Dim, dims, periods, 0, &comm_);
    MPI_Comm_rank(comm_, &rank_);
  }
  ~CartesianRanks() {
    if (comm_ != MPI_COMM_NULL) MPI_Comm_free(&comm_);
  }
  CartesianRanks(const CartesianRanks&) = delete;
  CartesianRanks& operator=(const CartesianRanks&) = delete;

  MPI_Comm comm() const { return comm_; }
  int rank() const { return rank_; }
  const BlockDecomposition<Dim>& blocks() const { return blocks_; }

 private:
  MPI_Comm comm_ = MPI_COMM_NULL;
  int rank_ = 0;
  BlockDecomposition<Dim> blocks_;
};

}  // namespace dgmpm::distributed
