#include "stability/courant_map.hpp"

#include "stability/admissible_courant.hpp"

#include <stdexcept>

namespace dgmpm::stability {

std::vector<double> two_particle_courant_map(int n, const std::vector<double>& masses,
                                             TimeScheme scheme, Criterion criterion, Model model) {
  if (n < 1) throw std::invalid_argument("the map needs at least one position per axis");
  if (!masses.empty() && masses.size() != 2)
    throw std::invalid_argument("--map needs two masses (one per particle) or none");
  validate(CellLayout{{0.5, 0.5}, masses});
  const bool symmetric = masses.empty() || masses[0] == masses[1];
  std::vector<double> c(static_cast<std::size_t>(n) * n);
  for (int i = 0; i < n; ++i)
    for (int j = 0; j < n; ++j) {
      if (symmetric && j < i) {  // swapping two equal particles leaves the layout unchanged
        c[i * n + j] = c[j * n + i];
        continue;
      }
      const CellLayout layout{{(i + 0.5) / n, (j + 0.5) / n}, masses};
      c[i * n + j] = admissible_courant(layout, scheme, criterion, model).courant;
    }
  return c;
}

}  // namespace dgmpm::stability
