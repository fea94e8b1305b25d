#pragma once
// The particle layout of one cell, the input of the von Neumann analysis (docs/method.md,
// "Stability").

#include <string>
#include <vector>

namespace dgmpm::stability {

// Positions are local coordinates in [0, 1], `dim` per particle (x, then y in 2D); masses are
// relative weights (equal when empty), scaled at use so that the cell's particles carry a full
// cell's mass, rho times the cell's volume.
struct CellLayout {
  std::vector<double> positions;
  std::vector<double> masses;
  int dim = 1;

  int size() const { return static_cast<int>(positions.size()) / dim; }
  double position(int k, int axis) const { return positions[k * dim + axis]; }
  // Relative weight of particle k, 1 when masses is empty.
  double weight(int k) const { return masses.empty() ? 1.0 : masses[k]; }
  // Fraction of the cell's mass carried by particle k.
  double mass_fraction(int k) const;
};

// Throws std::invalid_argument naming the offending entry: no particle, a position outside
// [0, 1] (or not a number), a non-positive or non-finite mass, or not as many masses as
// particles.
void validate(const CellLayout& layout);

// The layout seen by a wave travelling to -x: xi -> 1 - xi, same masses in the same order.
CellLayout mirror(const CellLayout& layout);
// 2D: the layout with x and y swapped.
CellLayout transpose(const CellLayout& layout);

// n equal particles at (k + 1/2) / n; in 2D n per axis, x fastest.
CellLayout regular_layout(int n, int dim = 1);

// "0.25, 0.75" style, for messages.
std::string describe(const std::vector<double>& values);
// The layout's positions: "0.25, 0.75" in 1D, "0.25:0.5, 0.75:0.5" in 2D.
std::string describe_positions(const CellLayout& layout);

}  // namespace dgmpm::stability
