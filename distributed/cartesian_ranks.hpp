#pragma once
// The ranks of an MPI communicator laid out over a grid: MPI_Dims_create chooses how many ranks
// go along each axis, MPI_Cart_create makes the topology (periodic where the grid is), and the
// block decomposition says which cells each rank owns (lib/dgmpm/decomposition.hpp; both number
// the ranks the same way, tests/distributed_cartesian_ranks.cpp checks it against MPI).

#include <dgmpm/decomposition.hpp>

#include <mpi.h>

#include <algorithm>
#include <array>
#include <type_traits>

#include <vector>

namespace dgmpm::distributed {

// The Cartesian topology over `world`'s ranks for axes periodic as given (no reordering: rank r
// of `world` is rank r of the result); `dims` receives the ranks along each axis: MPI_Dims_create's
// layout, or, given the grid's `cells` and that layout would cut an axis too thin, rank_layout's.
inline MPI_Comm cartesian_communicator(MPI_Comm world, const std::vector<bool>& periodic,
                                       std::vector<int>& dims, const std::vector<int>& cells = {}) {
  int size = 1;
  MPI_Comm_size(world, &size);
  const int n = static_cast<int>(periodic.size());
  dims.assign(n, 0);
  std::vector<int> periods(n);
  for (int l = 0; l < n; ++l) periods[l] = periodic[l] ? 1 : 0;
  MPI_Dims_create(size, n, dims.data());
  if (static_cast<int>(cells.size()) == n) {
    const auto choose = [&]<int D>(std::integral_constant<int, D>) {
      std::array<int, D> c{}, p{};
      std::array<bool, D> per{};
      for (int l = 0; l < D; ++l) c[l] = cells[l], p[l] = dims[l], per[l] = periodic[l];
      const auto chosen = rank_layout<D>(size, c, per, p);
      std::copy(chosen.begin(), chosen.end(), dims.begin());
    };
    if (n == 1) choose(std::integral_constant<int, 1>{});
    if (n == 2) choose(std::integral_constant<int, 2>{});
    if (n == 3) choose(std::integral_constant<int, 3>{});
  }
  MPI_Comm comm = MPI_COMM_NULL;
  MPI_Cart_create(world, n, dims.data(), periods.data(), 0, &comm);
  return comm;
}

template <int Dim>
class CartesianRanks {
 public:
  // Collective over `world`. Throws std::invalid_argument (on every rank) when MPI's layout puts
  // more ranks along an axis than the grid has cells.
  CartesianRanks(MPI_Comm world, const Grid<Dim>& grid) {
    std::vector<int> dims;
    comm_ = cartesian_communicator(
        world, std::vector<bool>(grid.periodic.begin(), grid.periodic.end()), dims);
    typename BlockDecomposition<Dim>::Index layout{};
    for (int l = 0; l < Dim; ++l) layout[l] = dims[l];
    MPI_Comm_rank(comm_, &rank_);
    try {
      blocks_ = BlockDecomposition<Dim>(grid, layout);
    } catch (...) {
      MPI_Comm_free(&comm_);
      throw;
    }
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
