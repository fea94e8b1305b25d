// Simulation for finite strain (see simulation_impl.hpp for why apart).
#include "solver/simulation_impl.hpp"

namespace dgmpm {

template class Simulation<FiniteStrainBar<SaintVenantKirchhoff>>;
template class Simulation<FiniteStrainBar<NeoHookean>>;

}  // namespace dgmpm
