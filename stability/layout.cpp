#include "stability/layout.hpp"

#include <cmath>
#include <sstream>
#include <stdexcept>

namespace dgmpm::stability {

double CellLayout::mass_fraction(int k) const {
  double total = 0.0;
  for (int j = 0; j < size(); ++j) total += weight(j);
  return weight(k) / total;
}

void validate(const CellLayout& layout) {
  if (layout.positions.empty()) throw std::invalid_argument("the layout has no particle");
  for (int k = 0; k < layout.size(); ++k) {
    const double x = layout.positions[k];
    if (!(x >= 0.0 && x <= 1.0)) {
      std::ostringstream s;
      s << "position " << k + 1 << " (" << x << ") is outside the cell: positions are local "
        << "coordinates in [0, 1]";
      throw std::invalid_argument(s.str());
    }
  }
  if (layout.masses.empty()) return;
  if (layout.masses.size() != layout.positions.size()) {
    std::ostringstream s;
    s << layout.masses.size() << " masses for " << layout.positions.size()
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
  for (double& x : m.positions) x = 1.0 - x;
  return m;
}

CellLayout regular_layout(int n) {
  if (n < 1) throw std::invalid_argument("a regular layout needs at least one particle");
  CellLayout layout;
  for (int k = 0; k < n; ++k) layout.positions.push_back((k + 0.5) / n);
  return layout;
}

std::string describe(const std::vector<double>& values) {
  std::ostringstream s;
  for (std::size_t k = 0; k < values.size(); ++k) s << (k ? ", " : "") << values[k];
  return s.str();
}

}  // namespace dgmpm::stability
