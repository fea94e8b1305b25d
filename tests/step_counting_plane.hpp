#pragma once
// A material that exists only in tests: plane strain with one internal variable, the number of
// steps its particle has taken, incremented by the per-particle step. Its waves are plane
// strain's to the bit; what it checks is that a physics with internal variables of its own runs
// through lib's sweeps (tests/lib_particle_fields.cpp) and the solver's loop, outputs and
// checkpoints (tests/solver_new_material.cpp) without a line of them changed
// (docs/architecture.md, "A material in four files").

#include <dgmpm/physics/plane_strain.hpp>

#include <array>

namespace dgmpm::testing {

struct StepCountingPlane : PlaneStrain {
  static constexpr int n_internal = 1;
  static constexpr std::array<const char*, n_internal> internal_names{"steps_taken"};
  static constexpr std::array<const char*, n_internal> internal_units{"1"};
  template <class Q, class Z>
  static void particle_step(Q&&, Z&& z, const Material&, double) {
    z[0] += 1;
  }
};

}  // namespace dgmpm::testing
