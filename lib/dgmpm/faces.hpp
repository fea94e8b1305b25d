#pragma once
// The faces of a grid's cells, as the DG operator reads them: which cells a face joins and which
// faces a cell has (FaceTopology), and what condition a face on a grid side carries, with its
// value at a time (BoundaryFaces). Built once per operator; plain tables read in the sweeps.

#include "boundary.hpp"
#include "grid.hpp"

#include <Eigen/Core>
#include <algorithm>
#include <array>
#include <utility>
#include <vector>

namespace dgmpm {

// Faces normal to axis l, indexed like cells but with cells[l] + 1 positions along l on a
// non-periodic axis: face k lies between cell k - e_l (minus) and cell k (plus); -1 for a side
// outside the grid.
template <int Dim>
class FaceTopology {
 public:
  using Index = typename Grid<Dim>::Index;

  explicit FaceTopology(const Grid<Dim>& grid) {
    for (int l = 0, stride = 1; l < Dim; stride *= grid.cells[l], ++l) stride_[l] = stride;
    for (int l = 0; l < Dim; ++l) tabulate(grid, l);
  }

  int num_faces(int l) const { return static_cast<int>(cells_[l].size()); }
  // (minus, plus) cells of face f along l.
  const std::pair<int, int>& cells(int l, int f) const { return cells_[l][f]; }
  // Cell c's face along l on `side` (0: lower, 1: upper).
  int of_cell(int l, int c, int side) const { return faces_[l][2 * c + side]; }
  // Cell index stride along axis l.
  int stride(int l) const { return stride_[l]; }
  // Face f's position (the index of its plus cell, or one past the grid along l).
  Index position(int l, int f) const {
    Index k{};
    for (int a = 0; a < Dim; ++a) {
      k[a] = f % extent_[l][a];
      f /= extent_[l][a];
    }
    return k;
  }

 private:
  void tabulate(const Grid<Dim>& grid, int l) {
    std::array<int, Dim>& extent = extent_[l];
    extent = grid.cells;
    if (!grid.periodic[l]) extent[l] += 1;
    int count = 1;
    for (int k = 0; k < Dim; ++k) count *= extent[k];
    cells_[l].resize(count);
    faces_[l].resize(2 * static_cast<std::size_t>(grid.num_cells()));
    for (int f = 0; f < count; ++f) {
      const Index k = position(l, f);
      int plus = -1, minus = -1;
      if (k[l] < grid.cells[l]) {
        plus = grid.flatten(k);
        faces_[l][2 * plus] = f;
        minus = grid.neighbour(plus, l, 0);
      } else {
        auto km = k;
        km[l] -= 1;
        minus = grid.flatten(km);
      }
      if (minus >= 0) faces_[l][2 * minus + 1] = f;
      cells_[l][f] = {minus, plus};
    }
  }

  std::array<std::vector<std::pair<int, int>>, Dim> cells_;  // (minus, plus), -1 outside
  std::array<std::vector<int>, Dim> faces_;                  // [2 c + side] -> face
  std::array<std::array<int, Dim>, Dim> extent_{};           // faces along each axis, per l
  std::array<int, Dim> stride_{};
};

// The conditions of the faces on the grid's sides (the boundaries are referenced: their time
// tables must outlive this). A face's condition is the segment covering its midpoint, unless that
// is a traction or nothing: then the tractions of all segments covering part of the face, each
// times its covered fraction (the applied force is exact), or free.
template <int Dim>
class BoundaryFaces {
 public:
  using Vec = Eigen::Matrix<double, Dim, 1>;
  struct Condition {
    BoundaryKind kind = BoundaryKind::free;
    int begin = 0, end = 0;  // parts_[begin, end): (time table, covered fraction)
  };

  BoundaryFaces(const Grid<Dim>& grid, const FaceTopology<Dim>& faces,
                const Boundaries<Dim>& boundaries) {
    for (int l = 0; l < Dim; ++l)
      for (int f = 0; f < faces.num_faces(l); ++f) {
        const auto [minus, plus] = faces.cells(l, f);
        if (minus < 0 || plus < 0)
          resolve(grid, l, minus < 0 ? 0 : 1, faces.position(l, f), boundaries, f);
      }
  }

  // Face f's condition along l, nullptr if it is not on a grid side (a search: only boundary
  // faces ask).
  const Condition* at(int l, int f) const {
    const auto& faces = by_face_[l];
    const auto it = std::lower_bound(faces.begin(), faces.end(), std::pair{f, -1});
    return it != faces.end() && it->first == f ? &conditions_[it->second] : nullptr;
  }
  // The prescribed value of a condition at time t.
  Vec value(const Condition& c, double t) const {
    Vec v = Vec::Zero();
    for (int i = c.begin; i < c.end; ++i) v += parts_[i].second * (*parts_[i].first)(t);
    return v;
  }
  // Kind of the boundary that face f is for its occupied side: the grid side's condition, or a
  // free surface against a void cell.
  BoundaryKind kind(int l, int f) const {
    const Condition* c = at(l, f);
    return c ? c->kind : BoundaryKind::free;
  }
  // (axis, face) of the faces under traction or velocity.
  const std::vector<std::pair<int, int>>& loaded() const { return loaded_; }

 private:
  void resolve(const Grid<Dim>& grid, int l, int side, const typename Grid<Dim>::Index& k,
               const Boundaries<Dim>& boundaries, int f) {
    const BoundarySide<Dim>& bs = boundaries[l][side];
    Vec lo, hi;
    for (int a = 0; a < Dim; ++a) {
      lo[a] = grid.origin[a] + (grid.first[a] + k[a]) * grid.cell_size[a];
      hi[a] = lo[a] + grid.cell_size[a];
    }
    const Vec mid = 0.5 * (lo + hi);
    Condition c;
    c.begin = c.end = static_cast<int>(parts_.size());
    const BoundaryCondition<Dim>* at_mid = bs.at(mid, l);
    if (at_mid && at_mid->kind != BoundaryKind::traction) {
      c.kind = at_mid->kind;
      parts_.emplace_back(&at_mid->value, 1.0);
    } else {
      for (const auto& s : bs.segments) {
        if (s.condition.kind != BoundaryKind::traction) continue;
        double fraction = 1.0;
        for (int a = 0; a < Dim; ++a) {
          if (a == l) continue;
          const double overlap = std::min(s.hi[a], hi[a]) - std::max(s.lo[a], lo[a]);
          fraction *= std::max(0.0, overlap) / grid.cell_size[a];
        }
        if (fraction <= 0.0) continue;
        c.kind = BoundaryKind::traction;
        parts_.emplace_back(&s.condition.value, fraction);
      }
    }
    c.end = static_cast<int>(parts_.size());
    by_face_[l].emplace_back(f, static_cast<int>(conditions_.size()));  // f increases
    conditions_.push_back(c);
    if (c.kind == BoundaryKind::traction || c.kind == BoundaryKind::velocity)
      loaded_.emplace_back(l, f);
  }

  // The grid sides' faces of each axis, by increasing face: (face, index into conditions_).
  std::array<std::vector<std::pair<int, int>>, Dim> by_face_;
  std::vector<Condition> conditions_;
  std::vector<std::pair<const TimeTable<Dim>*, double>> parts_;
  std::vector<std::pair<int, int>> loaded_;
};

}  // namespace dgmpm
