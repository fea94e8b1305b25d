#pragma once
// Fixed Cartesian grid of cells. Every cell owns its 2^Dim nodes (broken shape functions), so
// node ids are cell * nodes_per_cell + local, local's bit l being the node's side along axis l.

#include <Eigen/Core>
#include <algorithm>
#include <array>
#include <cmath>

namespace dgmpm {

template <int Dim>
struct Grid {
  static_assert(Dim >= 1 && Dim <= 3, "dgmpm grids are 1D, 2D or 3D");
  static constexpr int dim = Dim;
  static constexpr int nodes_per_cell = 1 << Dim;
  using Vec = Eigen::Matrix<double, Dim, 1>;
  using Index = std::array<int, Dim>;

  Vec origin = Vec::Zero();
  Vec cell_size = Vec::Ones();
  Index cells{};
  std::array<bool, Dim> periodic{};
  // A window onto a larger grid (a rank's cells and its ghost layers in a distributed run): cell
  // k of the window is cell first + k of the full grid (origin: the full grid's; cells and
  // periodic axes: `full`), wrapped along the full grid's periodic axes. Positions are located
  // in the full grid with its arithmetic, so a particle's local coordinates are the same to the
  // bit in a window as in the full grid. full.cells zero on an axis: the grid is not a window.
  struct Full {
    Index cells{};
    std::array<bool, Dim> periodic{};
  };
  Index first{};
  Full full{};

  int num_cells() const {
    int n = 1;
    for (int l = 0; l < Dim; ++l) n *= cells[l];
    return n;
  }
  int num_nodes() const { return num_cells() * nodes_per_cell; }
  double cell_volume() const { return cell_size.prod(); }
  double length(int axis) const { return cells[axis] * cell_size[axis]; }
  double upper(int axis) const { return origin[axis] + length(axis); }

  Index unflatten(int c) const {
    Index k{};
    for (int l = 0; l < Dim; ++l) {
      k[l] = c % cells[l];
      c /= cells[l];
    }
    return k;
  }
  int flatten(const Index& k) const {
    int c = 0;
    for (int l = Dim - 1; l >= 0; --l) c = c * cells[l] + k[l];
    return c;
  }

  // Cell across the face of cell c normal to `axis` on `side` (0: minus, 1: plus); -1 on a
  // non-periodic boundary.
  int neighbour(int c, int axis, int side) const {
    Index k = unflatten(c);
    k[axis] += side ? 1 : -1;
    if (k[axis] < 0 || k[axis] >= cells[axis]) {
      if (!periodic[axis]) return -1;
      k[axis] = (k[axis] + cells[axis]) % cells[axis];
    }
    return flatten(k);
  }

  // Relative distance to a face (in cells) under which a point counts as on the face: particles
  // that reach a face together must land in the same cell, whatever their round-off.
  static constexpr double face_snap = 1e-12;

  // Cell holding x and the local coordinates xi in [0, 1]^Dim; -1 when x is outside a
  // non-periodic grid. A point on a face belongs to the cell on its plus side, except on the
  // grid's upper boundary, which belongs to the last cell (xi = 1). Periodic axes wrap x.
  // In a window: the full grid's cell and coordinates, then -1 when the window does not hold
  // that cell.
  int locate(const Vec& x, Vec& xi) const {
    Index k{};
    for (int l = 0; l < Dim; ++l) {
      const bool window = full.cells[l] > 0;
      const int n = window ? full.cells[l] : cells[l];
      const bool wrap = window ? full.periodic[l] : periodic[l];
      double s = (x[l] - origin[l]) / cell_size[l];
      // rint, not round: inlined rather than a call (a fifth of locate's instructions). They
      // differ only at a tie, half a cell from a face, which no snap reaches below 5e11 cells.
      const double face = std::rint(s);
      if (std::abs(s - face) <= face_snap * std::max(1.0, std::abs(face))) s = face;
      if (!(s > 0.0 && s < n)) {  // inside, s is already its own wrap (s / n floors to 0)
        if (wrap) {
          if (!std::isfinite(s)) return -1;  // as off a non-periodic axis (no int of a NaN)
          s -= std::floor(s / n) * n;
          if (s >= n) s = 0.0;  // round-off of the wrap
        } else if (!(s >= 0.0 && s <= n)) {
          return -1;  // also catches NaN
        }
      }
      // s >= 0 here (or -0), so truncation is floor. The wrap is not negative: s / n rounds up to
      // an integer m only within an ulp of it, where the snap has made s exactly m n.
      int kl = static_cast<int>(s);
      if (kl == n) kl = n - 1;
      xi[l] = s - kl;
      if (window) {
        kl -= first[l];
        if (wrap) kl = (kl % n + n) % n;
        if (kl < 0 || kl >= cells[l]) return -1;
      }
      k[l] = kl;
    }
    return flatten(k);
  }
};

}  // namespace dgmpm
