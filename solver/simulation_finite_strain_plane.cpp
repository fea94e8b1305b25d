// Simulation for 2D finite strain (see simulation_impl.hpp for why apart).
#include "solver/simulation_impl.hpp"

namespace dgmpm {

template class Simulation<FiniteStrainPlane<SaintVenantKirchhoff>>;
template class Simulation<FiniteStrainPlane<NeoHookean>>;

}  // namespace dgmpm
