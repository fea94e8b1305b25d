#include "stability/layout.hpp"

#include <algorithm>
#include <cmath>
#include <sstream>
#include <stdexcept>
#include <string>
#include <utility>

namespace dgmpm::stability {

double CellLayout::mass_fraction(int k) const {
  // Relative to the largest weight first: weights near the top of the double range (1e308 each)
  // would overflow their sum.
  double largest = 0.0;
  for (int j = 0; j < size(); ++j) largest = std::max(largest, weight(j));
  double total = 0.0;
  for (int j = 0; j < size(); ++j) total += weight(j) / largest;
  return weight(k) / largest / total;
}

void validate(const CellLayout& layout) {
  if (layout.positions.empty()) throw std::invalid_argument("the layout has no particle");
  if (layout.dim < 1 || layout.positions.size() % static_cast<std::size_t>(layout.dim) != 0)
    throw std::invalid_argument("the layout's coordinates are not " + std::to_string(layout.dim) +
                                " per particle");
  for (int k = 0; k < layout.size(); ++k)
    for (int a = 0; a < layout.dim; ++a) {
      const double x = layout.position(k, a);
      if (!(x >= 0.0 && x <= 1.0)) {
        std::ostringstream s;
        s << "position " << k + 1 << " (" << x << ") is outside the cell: positions are local "
          << "coordinates in [0, 1]";
        throw std::invalid_argument(s.str());
      }
    }
  if (layout.masses.empty()) return;
  if (layout.masses.size() != static_cast<std::size_t>(layout.size())) {
    std::ostringstream s;
    s << layout.masses.size() << " masses for " << layout.size()
      << " positions: give one mass per position (or none for equal masses)";
    throw std::invalid_argument(s.str());
  }
  for (std::size_t k = 0; k < layout.masses.size(); ++k) {
    const double m = layout.masses[k];
    if (!(m > 0.0 && std::isfinite(m))) {
      std::ostringstream s;
      s << "mass " << k + 1 << " (" << m << ") must be positive and finite";
      throw std::invalid_argument(s.str());
    }
  }
}

CellLayout mirror(const CellLayout& layout) {
  CellLayout m = layout;
  for (int k = 0; k < m.size(); ++k) m.positions[k * m.dim] = 1.0 - m.positions[k * m.dim];
  return m;
}

CellLayout transpose(const CellLayout& layout) {
  CellLayout t = layout;
  if (t.dim == 2)
    for (int k = 0; k < t.size(); ++k) std::swap(t.positions[2 * k], t.positions[2 * k + 1]);
  return t;
}

CellLayout regular_layout(int n, int dim) {
  if (n < 1) throw std::invalid_argument("a regular layout needs at least one particle");
  CellLayout layout;
  layout.dim = dim;
  if (dim == 1) {
    for (int k = 0; k < n; ++k) layout.positions.push_back((k + 0.5) / n);
  } else {
    for (int j = 0; j < n; ++j)
      for (int i = 0; i < n; ++i) {
        layout.positions.push_back((i + 0.5) / n);
        layout.positions.push_back((j + 0.5) / n);
      }
  }
  return layout;
}

std::string describe_positions(const CellLayout& layout) {
  std::ostringstream s;
  for (int k = 0; k < layout.size(); ++k) {
    s << (k ? ", " : "");
    for (int a = 0; a < layout.dim; ++a) s << (a ? ":" : "") << layout.position(k, a);
  }
  return s.str();
}

std::string describe(const std::vector<double>& values) {
  std::ostringstream s;
  for (std::size_t k = 0; k < values.size(); ++k) s << (k ? ", " : "") << values[k];
  return s.str();
}

}  // namespace dgmpm::stability
