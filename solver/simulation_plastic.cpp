// Simulation for the physics with internal variables (see simulation_impl.hpp for why apart).
#include "solver/simulation_impl.hpp"

namespace dgmpm {

template class Simulation<ElastoPlasticBar>;
template class Simulation<PlaneStrainPlastic>;
template class Simulation<UniaxialStrainPlastic>;

}  // namespace dgmpm
