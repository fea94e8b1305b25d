#pragma once
// Whole-scene stability (docs/method.md, "Stability"): the largest-magnitude eigenvalues of
// the global one-step operator of a DGMPM scene, each product being one step of lib's integrator
// on the scene's actual particles and boundaries (boundary values set to zero: the operator's
// linear part), and the largest Courant number at which its spectral radius stays at most 1.

#include "solver/scene.hpp"

#include <iosfwd>
#include <string>

namespace dgmpm {

struct SceneSpectrumResult {
  double courant = 0;                  // largest C with rho <= 1 + tolerance on (0, C]
  double failing_courant = 0;          // first C found failing above it
  bool bounded = true;                 // false: nothing failed up to the search's maximum
  double radius_at_scene_courant = 0;  // rho at the scene's own Courant number (fixed Courant only)
  int unknowns = 0;
  int evaluations = 0;
  std::string boundaries;  // periodic / reflecting
  std::string note;        // why the spectrum speaks for these boundaries
  std::string method;      // how the spectra were computed
};

// Throws scene::SceneError for a scene this does not apply to (MPM).
SceneSpectrumResult analyse_scene_spectrum(const scene::Scene& scene, double tolerance = 1e-8);

// `dgmpm courant --scene PATH [--json]`: prints the result; returns the exit code.
int scene_courant_command(const std::string& path, bool json, std::ostream& out, std::ostream& err);

}  // namespace dgmpm
