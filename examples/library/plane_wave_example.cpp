// dgmpm as a library: a 2D scene built in code (a P plane wave on a doubly periodic grid), run
// through the solver's API, its stress error against the exact translated wave checked, and
// one Courant number asked of the stability analysis directly.
//   plane_wave_example [--cells N]    exit 0 when the error is below 5% and C* is 1
#include <solver/scene.hpp>
#include <solver/simulation.hpp>
#include <stability/admissible_courant.hpp>

#include <nlohmann/json.hpp>

#include <cstdio>
#include <cstring>
#include <string>

int main(int argc, char** argv) {
  int cells = 24;
  if (argc == 3 && std::strcmp(argv[1], "--cells") == 0) cells = std::stoi(argv[2]);
  const double h = 1.0 / cells;
  const nlohmann::json doc = {
      {"dimension", 2},
      {"method", "dgmpm"},
      {"flux", "dcu"},
      {"grid",
       {{"origin", {0.0, 0.0}},
        {"cell_size", {h, h}},
        {"cells", {cells, cells}},
        {"periodic", true}}},
      {"materials", {{"steel", {{"young", 2e11}, {"poisson", 0.3}, {"density", 7800}}}}},
      {"bodies",
       {{{"material", "steel"},
         {"box", {{"min", {0.0, 0.0}}, {"max", {1.0, 1.0}}}},
         {"particles_per_cell", {1, 1}}}}},
      {"plane_wave", {{"wave", "p"}, {"cycles", {1, 0}}, {"amplitude", 1.0}}},
      {"exact", "plane_wave"},
      {"time", {{"end", 1e-4}, {"integrator", "rk2"}, {"courant", "auto"}}}};
  const dgmpm::scene::Scene scene = dgmpm::scene::parse_scene(doc, "plane_wave_example");
  dgmpm::PlaneStrainSimulation simulation(scene);
  const dgmpm::RunSummary summary = simulation.run();
  const double error = summary.stress_errors->l2;
  std::printf("%d x %d cells, %ld steps, relative L2 stress error %.3e\n", cells, cells,
              summary.steps, error);

  dgmpm::stability::CellLayout centred;
  centred.dim = 2;
  centred.positions = {0.5, 0.5};
  dgmpm::stability::AnalysisSetting setting;
  setting.dim = 2;
  setting.time = dgmpm::stability::TimeScheme::rk2;
  const double courant =
      dgmpm::stability::admissible_courant(centred, setting, dgmpm::stability::Criterion::l2)
          .courant;
  std::printf("admissible Courant number of one centred particle, RK2 DCU: %.7g\n", courant);
  return error < 0.05 && courant == 1.0 ? 0 : 1;
}
