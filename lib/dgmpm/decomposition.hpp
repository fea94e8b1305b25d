#pragma once
// Block decomposition of a grid over ranks laid out as a Cartesian array (docs/distributed.md):
// each rank owns a box of cells, contiguous along every axis and balanced to within one layer,
// and reads ghost layers of cells around it, one per stage (DCU couples face neighbours, CTU
// corner neighbours too): its window of the grid. Rank numbers and coordinates follow MPI's
// Cartesian topologies (the first axis varies slowest), so MPI_Cart_create's ranks and this
// decomposition agree; nothing here calls MPI.

#include "grid.hpp"

#include <algorithm>
#include <array>
#include <stdexcept>
#include <string>

namespace dgmpm {

template <int Dim>
struct BlockDecomposition {
  using Index = std::array<int, Dim>;

  Index cells{};  // the grid's cells along each axis
  Index ranks{};  // ranks along each axis
  std::array<bool, Dim> periodic{};

  BlockDecomposition() = default;
  // Throws std::invalid_argument when an axis would have more ranks than cells.
  BlockDecomposition(const Grid<Dim>& grid, const Index& rank_layout)
      : cells(grid.cells), ranks(rank_layout), periodic(grid.periodic) {
    for (int l = 0; l < Dim; ++l)
      if (ranks[l] < 1 || ranks[l] > cells[l])
        throw std::invalid_argument("decomposition: " + std::to_string(ranks[l]) +
                                    " ranks along axis " + std::to_string(l) + " of " +
                                    std::to_string(cells[l]) + " cells (allowed: 1 to the cells)");
  }

  int num_ranks() const {
    int n = 1;
    for (int l = 0; l < Dim; ++l) n *= ranks[l];
    return n;
  }

  // The first cell along `axis` of block k (k = ranks[axis]: one past the last cell), split as
  // OpenMP's threads split their ranges: sizes differ by one at most.
  int first_cell(int axis, int k) const {
    return static_cast<int>(static_cast<long>(cells[axis]) * k / ranks[axis]);
  }
  // The block along `axis` that owns cell i: the largest k with first_cell(axis, k) <= i.
  int block_of(int axis, int i) const {
    return static_cast<int>((static_cast<long>(i + 1) * ranks[axis] - 1) / cells[axis]);
  }

  // Rank from coordinates (MPI_Cart_rank's order), wrapping periodic axes; -1 past a
  // non-periodic side.
  int rank(Index coords) const {
    int r = 0;
    for (int l = 0; l < Dim; ++l) {
      if (coords[l] < 0 || coords[l] >= ranks[l]) {
        if (!periodic[l]) return -1;
        coords[l] = (coords[l] % ranks[l] + ranks[l]) % ranks[l];
      }
      r = r * ranks[l] + coords[l];
    }
    return r;
  }
  Index coords(int rank) const {
    Index k{};
    for (int l = Dim - 1; l >= 0; --l) {
      k[l] = rank % ranks[l];
      rank /= ranks[l];
    }
    return k;
  }
  // The rank at offset (each entry -1, 0 or 1) from `rank`: face neighbours have one non-zero
  // entry, edge and corner neighbours more; -1 past a non-periodic side.
  int neighbour(int rank, const Index& offset) const {
    Index k = coords(rank);
    for (int l = 0; l < Dim; ++l) k[l] += offset[l];
    return this->rank(k);
  }

  // The cells `rank` owns: [lower, upper) along each axis.
  Index lower(int rank) const {
    const Index k = coords(rank);
    Index lo{};
    for (int l = 0; l < Dim; ++l) lo[l] = first_cell(l, k[l]);
    return lo;
  }
  Index upper(int rank) const {
    const Index k = coords(rank);
    Index hi{};
    for (int l = 0; l < Dim; ++l) hi[l] = first_cell(l, k[l] + 1);
    return hi;
  }
  int owned_cells(int rank) const {
    const Index lo = lower(rank), hi = upper(rank);
    int n = 1;
    for (int l = 0; l < Dim; ++l) n *= hi[l] - lo[l];
    return n;
  }
  // The window (grid.hpp) onto `grid` holding `rank`'s block and `depth` layers of cells around
  // it, clipped at non-periodic sides; periodic along an axis only if one rank spans it. Throws
  // std::invalid_argument when, along a periodic axis shared by several ranks, the block and its
  // layers would hold a cell twice.
  Grid<Dim> window(const Grid<Dim>& grid, int rank, int depth) const {
    Grid<Dim> w = grid;
    const Index lo = lower(rank), hi = upper(rank);
    for (int l = 0; l < Dim; ++l) {
      w.full.cells[l] = cells[l];
      w.full.periodic[l] = periodic[l];
      w.periodic[l] = periodic[l] && ranks[l] == 1;
      int begin = lo[l] - depth, end = hi[l] + depth;
      if (w.periodic[l]) {
        begin = 0;
        end = cells[l];
      } else if (!periodic[l]) {
        begin = std::max(begin, 0);
        end = std::min(end, cells[l]);
      } else if (end - begin > cells[l]) {
        throw std::invalid_argument("decomposition: a block of " + std::to_string(hi[l] - lo[l]) +
                                    " cells and " + std::to_string(depth) +
                                    " ghost layers on each side exceed the " +
                                    std::to_string(cells[l]) + " cells of periodic axis " +
                                    std::to_string(l) + " (allowed: fewer ranks along it)");
      }
      w.first[l] = begin;
      w.cells[l] = end - begin;
    }
    return w;
  }

  // The rank owning the cell with grid index k.
  int owner(const Index& k) const {
    Index b{};
    for (int l = 0; l < Dim; ++l) b[l] = block_of(l, k[l]);
    return rank(b);
  }
};

// The ranks along each axis for `ranks` ranks on a grid of `cells` (periodic where it is):
// `preferred` (MPI_Dims_create's balanced layout, blind to the grid) when each axis it splits
// keeps at least kMinBlock cells per rank, else, of the layouts that do, the one cutting the
// fewest cell faces (a thin strip goes along its length); `preferred` when none does (the
// decomposition then says why).
inline constexpr int kMinBlock = 4;
template <int Dim>
std::array<int, Dim> rank_layout(int ranks, const std::array<int, Dim>& cells,
                                 const std::array<bool, Dim>& periodic,
                                 const std::array<int, Dim>& preferred) {
  using Index = std::array<int, Dim>;
  const auto fits = [&](const Index& d) {
    for (int l = 0; l < Dim; ++l)
      if (d[l] > 1 && cells[l] < kMinBlock * d[l]) return false;
    return true;
  };
  if (fits(preferred)) return preferred;
  const auto cut_faces = [&](const Index& d) {
    double faces = 0;
    for (int l = 0; l < Dim; ++l) {
      double across = 1;  // faces of one cut normal to axis l
      for (int k = 0; k < Dim; ++k)
        if (k != l) across *= cells[k];
      faces += (periodic[l] ? d[l] : d[l] - 1) * across;
    }
    return faces;
  };
  Index best = preferred, d{};
  double fewest = -1;
  // Every factorisation of `ranks` into Dim factors, the first axis's factor outermost.
  const auto search = [&](auto&& self, int axis, int left) -> void {
    if (axis == Dim - 1) {
      d[axis] = left;
      if (fits(d) && (fewest < 0 || cut_faces(d) < fewest)) fewest = cut_faces(d), best = d;
      return;
    }
    for (int f = 1; f <= left; ++f)
      if (left % f == 0) {
        d[axis] = f;
        self(self, axis + 1, left / f);
      }
  };
  search(search, 0, ranks);
  return best;
}

}  // namespace dgmpm
