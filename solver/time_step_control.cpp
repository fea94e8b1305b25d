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

}  // namespace dgmpm
