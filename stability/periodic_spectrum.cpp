#include "stability/periodic_spectrum.hpp"

#include "stability/criteria.hpp"
#include "stability/periodic_cells.hpp"

#include <numbers>

namespace dgmpm::stability {
namespace {

template <class Physics>
double radius(const CellLayout& layout, TimeScheme scheme, int cells, double courant,
              const ArpackOptions& options) {
  PeriodicCells<Physics> grid(layout, cells, AnalysisSetting{1, scheme});
  const int n = Physics::n_comp * grid.num_particles();
  return spectral_radius(
      n,
      [&](const double* x, double* y) {
        grid.state() = Eigen::Map<const typename PeriodicCells<Physics>::Field>(
            x, Physics::n_comp, grid.num_particles());
        grid.step(courant);
        Eigen::Map<typename PeriodicCells<Physics>::Field>(y, Physics::n_comp,
                                                           grid.num_particles()) = grid.state();
      },
      options);
}

}  // namespace

double periodic_grid_spectral_radius(const CellLayout& layout, TimeScheme scheme, Model model,
                                     int cells, double courant, const ArpackOptions& options) {
  return model == Model::advection ? radius<Advection<1>>(layout, scheme, cells, courant, options)
                                   : radius<ElasticBar>(layout, scheme, cells, courant, options);
}

double discrete_von_neumann_radius(const OneStepMap& map, int cells, double courant) {
  L2Criterion l2(map);
  double rho = 0.0;
  for (int k = 0; k < cells; ++k)
    rho = std::max(rho, l2.spectral_radius(courant, 2.0 * std::numbers::pi * k / cells));
  return rho;
}

}  // namespace dgmpm::stability
