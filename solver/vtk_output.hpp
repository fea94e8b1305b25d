#pragma once
// VTK XML output for ParaView: one UnstructuredGrid (.vtu) of particles (vertex cells) per output
// time with every field as point data, and a .pvd collection that opens them as one time series.
// Files are written atomically, like every other output.

#include <dgmpm/particles.hpp>
#include <dgmpm/physics/contract.hpp>
#include <dgmpm/physics/elastic_bar.hpp>
#include <dgmpm/physics/plane_strain.hpp>

#include <Eigen/Core>
#include <algorithm>
#include <cmath>
#include <optional>
#include <string>
#include <utility>
#include <vector>

namespace dgmpm::vtk {

// A named point-data array: `components` values per particle, particle after particle, and its
// SI unit ("1": dimensionless; empty: none, as for ids).
struct PointData {
  std::string name;
  int components = 1;
  std::vector<double> values;
  std::string unit;
};

// How a .vtu is written: arrays as raw little-endian bytes appended after the XML (8 bytes a
// value, against about 24 as text), or as ASCII; the data set's time in its FieldData
// (TimeValue), so a file opened on its own still knows it. The units of the arrays, points and
// time go in the FieldData too, as a string array "units" of "name: unit" entries.
struct VtuOptions {
  bool binary = true;
  std::optional<double> time;
};

// Writes particles at `positions` (Dim rows; missing coordinates 0) with the given point data.
void write_points(const std::string& path, const Eigen::MatrixXd& positions,
                  const std::vector<PointData>& data, const VtuOptions& options = {});

// The fields of a physics, from the particles' physical states (sigma, v) and, when given, the
// exact solution's: 1D the state's components by their names (stress, velocity; finite strain F,
// velocity, with the Cauchy stress as stress_tensor and F as deformation_gradient, 3 x 3, and
// the reference positions, the points being the current ones); 2D sigma_xx, sigma_yy, sigma_xy,
// sigma_zz, von_mises, velocity (3 components); the stress as a 3 x 3 tensor ("stress_tensor", row
// by row, for ParaView's tensor filters) and, where the physics defines it, the strain
// ("strain_tensor"); the displacement from the initial position (3 components) where particles
// track it (moving particles); mass, volume, size (the side of the particle's volume,
// volume^(1/dim): cell-sized glyphs), id and material in both; the physics' internal variables and
// derived outputs.
template <class Physics, class ParticleSet, class Field>
std::vector<PointData> point_data(const ParticleSet& particles,
                                  const std::vector<typename Physics::Material>& materials,
                                  const Field& physical, const std::optional<Field>& exact);

// Where the particles are drawn: their positions, or for a physics that keeps particles at their
// reference positions X and carries their displacement u, the current positions X + u.
template <class Physics, class ParticleSet>
Eigen::MatrixXd current_positions(const ParticleSet& particles) {
  Eigen::MatrixXd x = particles.position;
  if constexpr (physics::CarriesDisplacement<Physics>)
    for (Eigen::Index i = 0; i < x.cols(); ++i)
      x.col(i) += Physics::displacement_of(particles.internal.col(i));
  return x;
}

// The particles and their point_data() in one .vtu.
template <class Physics, class ParticleSet, class Field>
void write_particles(const std::string& path, const ParticleSet& particles,
                     const std::vector<typename Physics::Material>& materials,
                     const Field& physical, const std::optional<Field>& exact,
                     const VtuOptions& options = {}) {
  write_points(path, current_positions<Physics>(particles),
               point_data<Physics>(particles, materials, physical, exact), options);
}

// A .pvtu: the pieces (.vtu file names relative to it, one per rank of a distributed run, each
// written by write_points with arrays named as `data`'s) as one data set.
void write_piece_index(const std::string& path, const std::vector<std::string>& pieces,
                       const std::vector<PointData>& data);

// A .pvd collection of (time, file name relative to the .pvd).
void write_series(const std::string& path,
                  const std::vector<std::pair<double, std::string>>& files);

// --- implementation ----------------------------------------------------------------------------

namespace detail {
inline PointData row(const std::string& name, const Eigen::MatrixXd& field, int r,
                     const std::string& unit) {
  PointData d{name, 1, {}, unit};
  for (Eigen::Index i = 0; i < field.cols(); ++i) d.values.push_back(field(r, i));
  return d;
}
inline PointData vector3(const std::string& name, const Eigen::MatrixXd& field, int first,
                         int count, const std::string& unit) {
  PointData d{name, 3, {}, unit};
  for (Eigen::Index i = 0; i < field.cols(); ++i)
    for (int k = 0; k < 3; ++k) d.values.push_back(k < count ? field(first + k, i) : 0.0);
  return d;
}
}  // namespace detail

template <class Physics, class ParticleSet, class Field>
std::vector<PointData> point_data(const ParticleSet& particles,
                                  const std::vector<typename Physics::Material>& materials,
                                  const Field& physical, const std::optional<Field>& exact) {
  std::vector<PointData> data;
  const auto fields = [&](const Eigen::MatrixXd& s, const std::string& prefix) {
    PointData tensor{prefix + "stress_tensor", 9, {}, "Pa"};
    if constexpr (physics::FiniteStrainOutputs<Physics>) {
      // F's components (1D: F and the velocity) as scalars, the velocity as a vector in 2D, the
      // Cauchy stress and F as 3 x 3 tensors.
      constexpr int scalars = Physics::dim == 1 ? Physics::n_comp : Physics::n_comp - 2;
      for (int k = 0; k < scalars; ++k)
        data.push_back(
            detail::row(prefix + Physics::state_names[k], s, k, Physics::state_units[k]));
      if constexpr (Physics::dim == 2)
        data.push_back(detail::vector3(prefix + "velocity", s, scalars, 2, "m/s"));
      PointData f{prefix + "deformation_gradient", 9, {}, "1"};
      for (Eigen::Index i = 0; i < s.cols(); ++i) {
        const Eigen::Matrix3d sigma = Physics::cauchy_stress_tensor(
            s.col(i), particles.internal.col(i), materials[particles.material[i]]);
        const Eigen::Matrix3d g =
            Physics::deformation_gradient_tensor(s.col(i), particles.internal.col(i));
        for (int k = 0; k < 9; ++k) {
          tensor.values.push_back(sigma(k / 3, k % 3));
          f.values.push_back(g(k / 3, k % 3));
        }
      }
      data.push_back(std::move(tensor));
      data.push_back(std::move(f));
    } else if constexpr (Physics::dim == 1) {
      for (int k = 0; k < Physics::n_comp; ++k)
        data.push_back(
            detail::row(prefix + Physics::state_names[k], s, k, Physics::state_units[k]));
      for (Eigen::Index i = 0; i < s.cols(); ++i)
        for (int k = 0; k < 9; ++k) tensor.values.push_back(k == 0 ? s(0, i) : 0.0);
      data.push_back(std::move(tensor));
    } else {
      data.push_back(detail::row(prefix + "sigma_xx", s, PlaneStrain::sxx, "Pa"));
      data.push_back(detail::row(prefix + "sigma_yy", s, PlaneStrain::syy, "Pa"));
      data.push_back(detail::row(prefix + "sigma_xy", s, PlaneStrain::sxy, "Pa"));
      PointData zz{prefix + "sigma_zz", 1, {}, "Pa"}, vm{prefix + "von_mises", 1, {}, "Pa"};
      for (Eigen::Index i = 0; i < s.cols(); ++i) {
        const auto& m = materials[particles.material[i]];
        const double xx = s(PlaneStrain::sxx, i), yy = s(PlaneStrain::syy, i);
        const double xy = s(PlaneStrain::sxy, i),
                     z = Physics::sigma_zz(s.col(i), m, particles.internal.col(i));
        zz.values.push_back(z);
        vm.values.push_back(
            std::sqrt(0.5 * ((xx - yy) * (xx - yy) + (yy - z) * (yy - z) + (z - xx) * (z - xx)) +
                      3.0 * xy * xy));
      }
      for (Eigen::Index i = 0; i < s.cols(); ++i) {
        const double xx = s(PlaneStrain::sxx, i), yy = s(PlaneStrain::syy, i);
        const double xy = s(PlaneStrain::sxy, i), z = zz.values[static_cast<std::size_t>(i)];
        for (double v : {xx, xy, 0.0, xy, yy, 0.0, 0.0, 0.0, z}) tensor.values.push_back(v);
      }
      data.push_back(zz);
      data.push_back(vm);
      data.push_back(detail::vector3(prefix + "velocity", s, PlaneStrain::vx, 2, "m/s"));
      data.push_back(std::move(tensor));
    }
  };
  fields(physical, "");
  if constexpr (physics::HasStrain<Physics>) {
    PointData strain{"strain_tensor", 9, {}, "1"};
    for (Eigen::Index i = 0; i < physical.cols(); ++i) {
      const Eigen::Matrix3d e = Physics::strain_tensor(physical.col(i), particles.internal.col(i),
                                                       materials[particles.material[i]]);
      for (int r = 0; r < 3; ++r)
        for (int c = 0; c < 3; ++c) strain.values.push_back(e(r, c));
    }
    data.push_back(std::move(strain));
  }
  if (particles.tracks_reference)
    data.push_back(detail::vector3("displacement", particles.position - particles.reference, 0,
                                   Physics::dim, "m"));
  if constexpr (physics::CarriesDisplacement<Physics>)  // the points are the current positions
    data.push_back(detail::vector3("reference_position", particles.position, 0, Physics::dim, "m"));
  if (exact) fields(*exact, "exact_");
  // Per unit thickness in 2D (kg/m, m^2), per unit cross-section in 1D (kg/m^2, m).
  const char* mass_unit = Physics::dim == 1 ? "kg/m^2" : "kg/m";
  PointData mass{"mass", 1, {}, mass_unit},
      volume{"volume", 1, {}, Physics::dim == 1 ? "m" : "m^2"}, size{"size", 1, {}, "m"},
      id{"id", 1, {}, ""}, mat{"material", 1, {}, ""};
  for (int i = 0; i < particles.size(); ++i) {
    mass.values.push_back(particles.mass[i]);
    volume.values.push_back(particles.volume[i]);
    size.values.push_back(std::pow(particles.volume[i], 1.0 / Physics::dim));
    id.values.push_back(particles.id[i]);
    mat.values.push_back(particles.material[i]);
  }
  for (auto* d : {&mass, &volume, &size, &id, &mat}) data.push_back(std::move(*d));
  for (int k = 0; k < ParticleSet::n_internal; ++k)  // the physics' internal variables
    data.push_back(
        detail::row(Physics::internal_names[k], particles.internal, k, Physics::internal_units[k]));
  if constexpr (physics::DerivedOutputs<Physics>) {  // and its derived outputs not written above
    constexpr int n = static_cast<int>(Physics::derived_names.size());
    for (int k = 0; k < n; ++k) {
      const std::string name = Physics::derived_names[k];
      if (std::any_of(data.begin(), data.end(), [&](const PointData& d) { return d.name == name; }))
        continue;
      PointData d{name, 1, {}, Physics::derived_units[k]};
      for (int i = 0; i < particles.size(); ++i)
        d.values.push_back(Physics::derived(physical.col(i), particles.internal.col(i),
                                            materials[particles.material[i]])[k]);
      data.push_back(std::move(d));
    }
  }
  return data;
}

}  // namespace dgmpm::vtk
