#pragma once
// Boundary conditions of the grid's faces. Each is realised by a ghost state, chosen by the
// physics so that the boundary Riemann problem returns the prescribed value (method.md 3).

#include <Eigen/Core>
#include <algorithm>
#include <array>
#include <stdexcept>
#include <string>
#include <vector>

namespace dgmpm {

enum class BoundaryKind { free, fixed, traction, velocity };

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

// Value components: the traction vector or the velocity vector (Dim components).
template <int Dim>
struct BoundaryCondition {
  BoundaryKind kind = BoundaryKind::free;
  TimeTable<Dim> value;
};

// boundaries[axis][side], side 0 at the axis' lower end. Ignored on periodic axes.
template <int Dim>
using Boundaries = std::array<std::array<BoundaryCondition<Dim>, 2>, Dim>;

}  // namespace dgmpm
