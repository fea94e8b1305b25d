#pragma once
// A particle set made awkward for a step: massless nodes, over-full and part-full cells.

#include <dgmpm/grid.hpp>

#include <Eigen/Core>

namespace dgmpm::test {

// Moves every 7th particle onto its cell's lower corner (a node massless along every axis) and
// every 11th into the next cell along x (over-full and part-full cells inside the body).
template <class ParticleSet, int Dim>
void disturb(ParticleSet& p, const Grid<Dim>& grid) {
  for (int k = 0; k < p.size(); k += 7) {
    Eigen::Matrix<double, Dim, 1> xi;
    const int c = grid.locate(p.position.col(k), xi);
    const auto index = grid.unflatten(c);
    for (int a = 0; a < Dim; ++a) p.position(a, k) = grid.origin[a] + index[a] * grid.cell_size[a];
  }
  for (int k = 3; k < p.size(); k += 11) p.position(0, k) += grid.cell_size[0];
}

}  // namespace dgmpm::test
