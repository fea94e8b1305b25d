#pragma once
// Boundary conditions of the grid's sides. A side holds segments, each with one condition on
// part of the side; what no segment covers is free. Each condition is realised by a ghost state,
// chosen by the physics so that the boundary Riemann problem returns the prescribed value.

#include <Eigen/Core>
#include <algorithm>
#include <array>
#include <limits>
#include <vector>

namespace dgmpm {

enum class BoundaryKind { free, fixed, traction, velocity, roller };

inline const char* to_string(BoundaryKind k) {
  switch (k) {
    case BoundaryKind::free:
      return "free";
    case BoundaryKind::fixed:
      return "fixed";
    case BoundaryKind::traction:
      return "traction";
    case BoundaryKind::velocity:
      return "velocity";
    case BoundaryKind::roller:
      return "roller";
  }
  return "?";
}

// Piecewise-linear function of time through (t_k, v_k), constant beyond its ends.
template <int N>
struct TimeTable {
  using Value = Eigen::Matrix<double, N, 1>;
  std::vector<double> times;
  std::vector<Value> values;

  static TimeTable constant(const Value& v) { return TimeTable{{0.0}, {v}}; }

  Value operator()(double t) const {
    if (values.empty()) return Value::Zero();
    if (values.size() == 1 || t <= times.front()) return values.front();
    if (t >= times.back()) return values.back();
    const auto it = std::upper_bound(times.begin(), times.end(), t);
    const std::size_t k = static_cast<std::size_t>(it - times.begin());
    const double w = (t - times[k - 1]) / (times[k] - times[k - 1]);
    return (1.0 - w) * values[k - 1] + w * values[k];
  }
};

// Traction: the prescribed (sigma_nn, sigma_nt) on the side (tension positive; in 1D sigma).
// Velocity: the prescribed velocity vector. Free, fixed and roller take no value.
template <int Dim>
struct BoundaryCondition {
  BoundaryKind kind = BoundaryKind::free;
  TimeTable<Dim> value;
};

// A condition on the points of a side whose coordinates lie in [lo, hi] along the side's
// tangential axes (the component along the side's normal is not read).
template <int Dim>
struct BoundarySegment {
  using Vec = Eigen::Matrix<double, Dim, 1>;
  BoundaryCondition<Dim> condition;
  Vec lo = Vec::Constant(-std::numeric_limits<double>::infinity());
  Vec hi = Vec::Constant(std::numeric_limits<double>::infinity());
};

template <int Dim>
struct BoundarySide {
  std::vector<BoundarySegment<Dim>> segments;  // disjoint

  BoundarySide() = default;
  // The whole side under one condition.
  BoundarySide(const BoundaryCondition<Dim>& whole) : segments{{whole}} {}  // NOLINT: implicit

  // The condition of the segment holding the tangential coordinates of x, or nullptr (free).
  const BoundaryCondition<Dim>* at(const Eigen::Matrix<double, Dim, 1>& x, int axis) const {
    for (const auto& s : segments) {
      bool inside = true;
      for (int l = 0; l < Dim; ++l)
        if (l != axis && !(s.lo[l] <= x[l] && x[l] <= s.hi[l])) inside = false;
      if (inside) return &s.condition;
    }
    return nullptr;
  }
};

// boundaries[axis][side], side 0 at the axis' lower end. Ignored on periodic axes.
template <int Dim>
using Boundaries = std::array<std::array<BoundarySide<Dim>, 2>, Dim>;

}  // namespace dgmpm
