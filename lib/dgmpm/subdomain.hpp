#pragma once
// One rank's part of a distributed run (docs/distributed.md): its block of cells, the window it
// steps on (the block and `depth` ghost layers: one per stage), the boundary conditions of that
// window, and the ranks it exchanges particles with. Plain code, no MPI: the solver's halo
// (solver/halo.hpp) moves the particles.

#include "boundary.hpp"
#include "decomposition.hpp"
#include "grid.hpp"

#include <array>
#include <vector>

namespace dgmpm {

template <int Dim>
class Subdomain {
 public:
  using Index = std::array<int, Dim>;
  using Vec = typename Grid<Dim>::Vec;

  // Throws std::invalid_argument when a window would hold a cell twice (decomposition.hpp).
  Subdomain(const Grid<Dim>& grid, const BlockDecomposition<Dim>& blocks, int rank, int depth)
      : full_(grid), blocks_(blocks), rank_(rank), window_(blocks.window(grid, rank, depth)) {
    const Index lo = blocks.lower(rank), hi = blocks.upper(rank);
    for (int q = 0; q < blocks.num_ranks(); ++q) {
      if (q == rank) continue;
      Grid<Dim> w = blocks.window(grid, q, depth);
      bool reaches = true;  // q's window holds a cell of this block along every axis
      for (int l = 0; l < Dim && reaches; ++l) {
        bool axis = false;
        for (int i = lo[l]; i < hi[l] && !axis; ++i) axis = holds_along(w, l, i);
        reaches = axis;
      }
      if (!reaches) continue;
      partners_.push_back(q);
      partner_windows_.push_back(std::move(w));
    }
  }

  int rank() const { return rank_; }
  const Grid<Dim>& full_grid() const { return full_; }
  const Grid<Dim>& window() const { return window_; }
  const BlockDecomposition<Dim>& blocks() const { return blocks_; }
  // The other ranks whose windows reach this block, in increasing order; by symmetry of the
  // layers, also those whose blocks this window reaches (the owners of its ghost cells).
  const std::vector<int>& partners() const { return partners_; }

  // The full grid's cell holding x (false outside the grid).
  bool locate(const Vec& x, Index& k) const {
    Vec xi;
    const int c = full_.locate(x, xi);
    if (c < 0) return false;
    k = full_.unflatten(c);
    return true;
  }
  int owner(const Index& k) const { return blocks_.owner(k); }
  bool owns(const Index& k) const { return owner(k) == rank_; }
  // Whether this rank's window, or partner j's (j an index into partners()), holds full cell k.
  bool holds(const Index& k) const { return holds(window_, k); }
  bool partner_holds(int j, const Index& k) const { return holds(partner_windows_[j], k); }
  // Full-grid index of window cell c.
  Index full_cell(int c) const {
    Index k = window_.unflatten(c);
    for (int l = 0; l < Dim; ++l) {
      k[l] += window_.first[l];
      const int n = full_.cells[l];
      if (k[l] < 0 || k[l] >= n) k[l] = (k[l] % n + n) % n;  // across a periodic side
    }
    return k;
  }

  // The window's conditions: the grid's on the sides it shares with the grid; free on the others,
  // which only the ghost cells touch (their new states are replaced by their owners').
  Boundaries<Dim> boundaries(const Boundaries<Dim>& grid_boundaries) const {
    Boundaries<Dim> b;
    for (int l = 0; l < Dim; ++l) {
      if (full_.periodic[l]) continue;  // window periodic (one rank along l) or sides inside
      if (window_.first[l] == 0) b[l][0] = grid_boundaries[l][0];
      if (window_.first[l] + window_.cells[l] == full_.cells[l]) b[l][1] = grid_boundaries[l][1];
    }
    return b;
  }

 private:
  static bool holds_along(const Grid<Dim>& w, int l, int i) {
    int k = i - w.first[l];
    if (w.full.periodic[l]) k = (k % w.full.cells[l] + w.full.cells[l]) % w.full.cells[l];
    return k >= 0 && k < w.cells[l];
  }
  static bool holds(const Grid<Dim>& w, const Index& k) {
    for (int l = 0; l < Dim; ++l)
      if (!holds_along(w, l, k[l])) return false;
    return true;
  }

  Grid<Dim> full_;
  BlockDecomposition<Dim> blocks_;
  int rank_ = 0;
  Grid<Dim> window_;
  std::vector<int> partners_;
  std::vector<Grid<Dim>> partner_windows_;
};

}  // namespace dgmpm
