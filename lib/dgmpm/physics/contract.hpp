#pragma once
// What a physics must provide, as concepts: the conservation law DCU's operator steps
// (ConservationLaw), what corner transport upwind adds in 2D (CornerTransport), what the MPM
// baseline needs of a constitutive model (MpmConstitutive), and the optional per-particle step
// after interpolation (ParticleStepPhysics: a constitutive correction such as a plastic return,
// with the physics' internal variables). The physics headers of this folder model them; the
// operator, the stepper and MPM state which they need, so a physics that misses a function is
// named at the point of use.

#include "../boundary.hpp"

#include <Eigen/Core>
#include <array>
#include <concepts>
#include <cstddef>
#include <type_traits>
#include <utility>

namespace dgmpm::physics {

// The per-particle internal variables of a physics (plastic strain, hardening...).
template <class P>
using Internal = Eigen::Matrix<double, P::n_internal, 1>;

// A boundary face's star state: the Riemann problem against a ghost state that makes it return
// the prescribed value (ghost), or, where no ghost state can (finite strain: the impedance changes
// with the state), the star state itself (boundary_star; side 1: the inside is the minus side).
template <class P>
concept GhostBoundary = requires(const typename P::State& q, const typename P::Material& m,
                                 int axis, BoundaryKind kind,
                                 const Eigen::Matrix<double, P::dim, 1>& value) {
  { P::ghost(kind, value, axis, q, m) } -> std::convertible_to<typename P::State>;
};
template <class P>
concept DirectBoundary = requires(const typename P::State& q, const typename P::Material& m,
                                  int axis, int side, BoundaryKind kind,
                                  const Eigen::Matrix<double, P::dim, 1>& value) {
  { P::boundary_star(kind, value, axis, q, m, side) } -> std::convertible_to<typename P::State>;
};

// A hyperbolic system q_t + div F(q) = 0 in specific form, as DCU's operator steps it: sizes,
// materials (one per cell, blended where a cell holds several), the volume term's flux, the
// Riemann problem of an edge, the flux of its star state and the star state of a boundary.
template <class P>
concept ConservationLaw = requires(const typename P::State& q, const typename P::Material& m,
                                   double mass, int axis) {
  requires P::dim >= 1 && P::dim <= 2;
  requires P::n_comp >= 1;
  requires P::n_internal >= 0;
  requires P::internal_names.size() == static_cast<std::size_t>(P::n_internal);
  requires P::internal_units.size() == static_cast<std::size_t>(P::n_internal);
  requires P::state_names.size() == static_cast<std::size_t>(P::n_comp);
  requires P::state_units.size() == static_cast<std::size_t>(P::n_comp);
  { P::max_wave_speed(m) } -> std::convertible_to<double>;
  { P::density(m) } -> std::convertible_to<double>;
  { P::blend(m, mass, m, mass) } -> std::convertible_to<typename P::Material>;
  { P::physical(q, m) } -> std::convertible_to<typename P::State>;
  { P::specific_flux(axis, q, m) } -> std::convertible_to<typename P::State>;
  { P::riemann(axis, q, m, q, m) } -> std::convertible_to<typename P::State>;
  { P::flux(axis, q, m) } -> std::convertible_to<typename P::State>;
  requires GhostBoundary<P> || DirectBoundary<P>;
};

// A physics whose volume-term flux specific_flux(axis, q, m) is linear in q declares
// `static constexpr bool linear_flux = true`: the operator may then take the flux of an
// interpolated state for the interpolation of the nodes' fluxes (tests/lib_volume_term.cpp checks
// the declaration).
template <class P>
concept LinearFlux = requires {
  requires P::linear_flux;
};

// CTU in 2D: the fluctuations entering a cell, their transverse split and what a boundary does to
// a transverse wave. The split is linearised in a "medium" per cell side of the crossed face: the
// cell's material, or, where the waves depend on the state (finite strain), what
// `transverse_medium(axis, q, m)` makes of the cell's edge state q there. `transverse` and
// `transverse_at_boundary` must be linear in the fluctuation: the operator splits the sum of the
// fluctuations entering a cell once (tests/lib_transverse_linearity.cpp).
template <class P>
concept StateDependentTransverse = requires(const typename P::State& q,
                                            const typename P::Material& m, int axis) {
  P::transverse_medium(axis, q, m);
};
template <class P>
struct TransverseMediumOf {
  using type = typename P::Material;
};
template <StateDependentTransverse P>
struct TransverseMediumOf<P> {
  using type = std::remove_cvref_t<decltype(P::transverse_medium(
      0, std::declval<const typename P::State&>(), std::declval<const typename P::Material&>()))>;
};
template <class P>
using TransverseMedium = typename TransverseMediumOf<P>::type;

template <class P>
concept CornerTransport = ConservationLaw<P> &&
    requires(const typename P::State& q, const typename P::Material& m,
             const TransverseMedium<P>& medium, int axis, int side, bool up, BoundaryKind kind) {
  { P::fluctuation(axis, q, q, m, side) } -> std::convertible_to<typename P::State>;
  { P::transverse(axis, q, medium, medium, up) } -> std::convertible_to<typename P::State>;
  {
    P::transverse_at_boundary(kind, axis, q, medium, up)
    } -> std::convertible_to<typename P::State>;
};

// What the operator needs: the conservation law; CTU also needs CornerTransport in 2D (the
// operator refuses "ctu" for a physics without it).
template <class P>
concept DGPhysics = ConservationLaw<P>;

// The MPM baseline's constitutive part: the Cauchy stress of a state and its rate update.
template <class P>
concept MpmConstitutive = ConservationLaw<P> &&
    requires(typename P::State& q, const typename P::Material& m,
             const Eigen::Matrix<double, P::dim, P::dim>& grad_v, double dt) {
  { P::stress_tensor(q, m) } -> std::convertible_to<Eigen::Matrix<double, P::dim, P::dim>>;
  P::add_stress_rate(q, grad_v, m, dt);
};

// The energy the solver reports, per unit mass: kinetic, and elastic from the state or, where the
// internal variables change it (plane strain's sigma_zz under plastic flow), from both.
template <class P>
concept HasEnergy = requires(const typename P::State& q) {
  { P::kinetic_energy_per_mass(q) } -> std::convertible_to<double>;
}
&&(
    requires(const typename P::State& q, const typename P::Material& m) {
      { P::elastic_energy_per_mass(q, m) } -> std::convertible_to<double>;
    } ||
    requires(const typename P::State& q, const Internal<P>& z, const typename P::Material& m) {
      { P::elastic_energy_per_mass(q, z, m) } -> std::convertible_to<double>;
    });

// A correction of a particle's state q and internal variables z over a step dt, once q is
// interpolated (a return mapping). Physics with internal variables must have one.
template <class P>
concept ParticleStepPhysics = requires(typename P::State& q, Internal<P>& z,
                                       const typename P::Material& m, double dt) {
  P::particle_step(q, z, m, dt);
};

// A physics whose internal variables store and dissipate energy (hardening, plastic flow): per
// unit mass, from a particle's internal variables.
template <class P>
concept Dissipative = requires(const Internal<P>& z, const typename P::Material& m) {
  { P::stored_energy_per_mass(z, m) } -> std::convertible_to<double>;
  { P::dissipated_energy_per_mass(z) } -> std::convertible_to<double>;
};

// Output columns a physics derives from a particle (sigma_zz, back stress...): their names, SI
// units and values from its physical state, internal variables and material.
template <class P>
concept DerivedOutputs = requires(const typename P::State& s, const Internal<P>& z,
                                  const typename P::Material& m) {
  P::derived_names.size();
  requires P::derived_units.size() == P::derived_names.size();
  { P::derived(s, z, m) } -> std::convertible_to<std::array<double, P::derived_names.size()>>;
};

// A physics whose particles have a strain (small strain: from the stress and the internal
// variables), as a 3 x 3 tensor for outputs.
template <class P>
concept HasStrain = requires(const typename P::State& s, const Internal<P>& z,
                             const typename P::Material& m) {
  { P::strain_tensor(s, z, m) } -> std::convertible_to<Eigen::Matrix3d>;
};

// A physics whose wave speeds change with the state (finite strain): the largest speed at a
// particle's specific state, NaN where the state leaves the hyperbolic range. A run recomputes its
// time step every step from these.
template <class P>
concept StateDependentSpeed = requires(const typename P::State& q, const typename P::Material& m) {
  { P::state_wave_speed(q, m) } -> std::convertible_to<double>;
};

// A physics whose particles stay at their reference positions X and carry a displacement u among
// their internal variables (total Lagrangian): outputs place them at X + u.
template <class P>
concept CarriesDisplacement = requires(const Internal<P>& z) {
  { P::displacement_of(z) } -> std::convertible_to<Eigen::Matrix<double, P::dim, 1>>;
};

// Outputs of a physics whose state is not the stress (finite strain): the Cauchy stress and the
// deformation gradient as 3 x 3 tensors.
template <class P>
concept FiniteStrainOutputs = requires(const typename P::State& s, const Internal<P>& z,
                                       const typename P::Material& m) {
  { P::cauchy_stress_tensor(s, z, m) } -> std::convertible_to<Eigen::Matrix3d>;
  { P::deformation_gradient_tensor(s, z) } -> std::convertible_to<Eigen::Matrix3d>;
};

template <class P>
concept InternalVariablesStepped = P::n_internal == 0 || ParticleStepPhysics<P>;

}  // namespace dgmpm::physics
