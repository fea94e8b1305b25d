#include "solver/time_step_control.hpp"

namespace dgmpm {

double LayoutQuantisation::quantise_position(double xi, double quantum) {
  const double d = std::min(xi, 1.0 - xi);              // distance to the nearest node
  if (!(d > 0.0)) return xi;                            // on a node (or not a number): as it is
  if (d < 0.5 * quantum) return xi <= 0.5 ? 0.0 : 1.0;  // below the resolution: on the node
  int exponent = 0;
  std::frexp(d, &exponent);  // d in [2^(exponent - 1), 2^exponent)
  const double step = std::min(quantum, std::ldexp(1.0, exponent - 1 - node_distance_bits));
  const double rounded = std::round(d / step) * step;  // >= 2^8 steps: never 0
  return xi <= 0.5 ? rounded : 1.0 - rounded;
}

const std::array<double, LayoutLattice::kPoints>& LayoutLattice::points() {
  static const std::array<double, kPoints> lattice = [] {
    std::array<double, kPoints> p{};
    int k = 0;
    p[k++] = 0.0;
    for (int j = kNear; j >= 1; --j) p[k++] = std::exp2(-4.0 - static_cast<double>(j) / kPerOctave);
    for (int u = kUniform / 16; u <= kUniform / 2; ++u) p[k++] = static_cast<double>(u) / kUniform;
    for (int m = kSide - 2; m >= 0; --m) p[k++] = 1.0 - p[m];  // the mirror image, 1/2 once
    return p;
  }();
  return lattice;
}

int LayoutLattice::box(double xi) {
  constexpr int first_uniform = kNear + 1;  // the index of 1/16
  if (xi >= 1.0 / 16 && xi < 15.0 / 16) {
    const int u = static_cast<int>(xi * kUniform);  // exact: kUniform is a power of 2
    return first_uniform + (u - kUniform / 16);
  }
  const auto& p = points();
  const auto it = std::upper_bound(p.begin(), p.end(), xi);
  return std::clamp(static_cast<int>(it - p.begin()) - 1, 0, kPoints - 2);
}

}  // namespace dgmpm
