#pragma once
// A grid of unit cells at the origin, given its cells and periodic axes (tests of the
// decomposition, serial and under MPI).

#include <dgmpm/grid.hpp>

#include <array>

namespace dgmpm::test {

template <int D>
Grid<D> grid(const std::array<int, D>& cells, const std::array<bool, D>& periodic) {
  Grid<D> g;
  g.cells = cells;
  g.periodic = periodic;
  return g;
}

}  // namespace dgmpm::test
