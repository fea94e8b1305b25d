#include "solver/simulation_impl.hpp"

namespace dgmpm {

// Instantiated in simulation_plastic.cpp.
extern template class Simulation<ElastoPlasticBar>;
extern template class Simulation<PlaneStrainPlastic>;
extern template class Simulation<UniaxialStrainPlastic>;
// Instantiated in simulation_finite_strain.cpp.
extern template class Simulation<FiniteStrainBar<SaintVenantKirchhoff>>;
extern template class Simulation<FiniteStrainBar<NeoHookean>>;
// Instantiated in simulation_finite_strain_plane.cpp.
extern template class Simulation<FiniteStrainPlane<SaintVenantKirchhoff>>;
extern template class Simulation<FiniteStrainPlane<NeoHookean>>;

StepperOptions stepper_options(const scene::Scene& scene) {
  return {scene.time.integrator, scene.flux, scene.formulation};
}

nlohmann::json RunSummary::to_json() const {
  nlohmann::json j = run.is_object() ? run : nlohmann::json::object();
  j["status"] = status;
  if (!reason.empty()) j["reason"] = reason;
  j["steps"] = steps;
  j["final_time"] = final_time;
  j["dt_min"] = dt_min;
  j["dt_max"] = dt_max;
  j["courant_min"] = courant_min;
  j["courant_max"] = courant_max;
  j["wall_seconds"] = wall_seconds;
  j["setup_seconds"] = setup_seconds;
  j["stepping_seconds"] = stepping_seconds;
  j["time_step_seconds"] = time_step_seconds;
  j["layout_analysis_seconds"] = layout_analysis_seconds;
  j["energy_initial"] = energy_initial;
  j["energy_final"] = energy_final;
  if (energy_stored) j["energy_stored"] = *energy_stored;
  if (energy_dissipated) j["energy_dissipated"] = *energy_dissipated;
  j["boundary_work"] = boundary_work;
  if (stress_errors && velocity_errors) {
    const auto norms = [](const ErrorNorms& e) {
      return nlohmann::json{{"l1", e.l1}, {"l2", e.l2}, {"max", e.max}};
    };
    j["errors"] = {{"stress", norms(*stress_errors)}, {"velocity", norms(*velocity_errors)}};
  }
  j["layouts_analysed"] = layouts_analysed;
  j["warnings"] = warnings;
  j["files"] = files;
  // SI units of the numbers here and in the run's files. 1D bars and 2D plane strain carry
  // extensive quantities per unit cross-section (1D) or per unit thickness (2D).
  const bool bar = j.value("dimension", 2) == 1;
  j["units"] = {{"time", "s"},
                {"length", "m"},
                {"velocity", "m/s"},
                {"stress", "Pa"},
                {"courant", "1"},
                {"errors", "1 (relative)"},
                {"seconds", "s (wall)"},
                {"energy", bar ? "J/m^2" : "J/m"},
                {"mass", bar ? "kg/m^2" : "kg/m"},
                {"volume", bar ? "m" : "m^2"}};
  return j;
}

ErrorNorms relative_errors(const Eigen::MatrixXd& computed, const Eigen::MatrixXd& exact,
                           const Eigen::VectorXd& volume, const Eigen::MatrixXd& fallback) {
  const Eigen::ArrayXd e = (computed - exact).colwise().norm().transpose().array();
  const auto norms = [&](const Eigen::ArrayXd& u) {
    return ErrorNorms{(volume.array() * u).sum(), std::sqrt((volume.array() * u.square()).sum()),
                      u.size() ? u.maxCoeff() : 0.0};
  };
  const ErrorNorms err = norms(e), ref = norms(exact.colwise().norm().transpose().array()),
                   alt = norms(fallback.colwise().norm().transpose().array());
  const auto scale = [](double r, double a) { return r > 0 ? r : (a > 0 ? a : 1.0); };
  return {err.l1 / scale(ref.l1, alt.l1), err.l2 / scale(ref.l2, alt.l2),
          err.max / scale(ref.max, alt.max)};
}

std::unique_ptr<SimulationBase> make_simulation(const scene::Scene& scene, Communicator* ranks) {
  return with_physics(scene, [&](auto physics) -> std::unique_ptr<SimulationBase> {
    return std::make_unique<Simulation<typename decltype(physics)::type>>(scene, ranks);
  });
}
template class Simulation<ElasticBar>;
template class Simulation<PlaneStrain>;

}  // namespace dgmpm
