#include "bench/solver_bench.hpp"

#include "solver/simulation.hpp"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <iomanip>
#include <nlohmann/json.hpp>

namespace dgmpm::bench {

namespace {

// A periodic steel bar carrying a sine wave: every cell holds one particle, nothing leaves.
scene::Scene bar_scene(int cells, const std::string& method, const std::string& integrator,
                       bool move) {
  const double length = 1.0;
  nlohmann::json doc = {{"dimension", 1},
                        {"method", method},
                        {"grid",
                         {{"origin", {0.0}},
                          {"cell_size", {length / cells}},
                          {"cells", {cells}},
                          {"periodic", true}}},
                        {"materials", {{"steel", {{"young", 2e11}, {"density", 7800}}}}},
                        {"bodies",
                         {{{"material", "steel"},
                           {"box", {{"min", {0.0}}, {"max", {length}}}},
                           {"particles_per_cell", 1},
                           {"velocity", {1.0}}}}},
                        {"time", {{"end", 1.0}, {"integrator", integrator}, {"courant", 0.5}}},
                        {"particles_move", move}};
  return scene::parse_scene(doc, "bench");
}

// Best of several timed batches of steps (the minimum is the least disturbed by other load).
double particle_steps_per_second(Simulation& sim, double seconds) {
  using clock = std::chrono::steady_clock;
  const double dt = sim.stable_time_step();
  sim.step(dt);  // warm-up: buffers allocated
  int batch = 1;
  double best = 0.0, spent = 0.0;
  while (spent < seconds) {
    const auto t0 = clock::now();
    for (int k = 0; k < batch; ++k) sim.step(dt);
    const double s = std::chrono::duration<double>(clock::now() - t0).count();
    spent += s;
    best = std::max(best, batch * static_cast<double>(sim.particles().size()) / s);
    if (s < 0.05) batch *= 2;
  }
  return best;
}

}  // namespace

void run_solver_benchmark(std::ostream& out, const std::vector<int>& particle_counts,
                          double seconds) {
  struct Case {
    const char* label;
    const char* method;
    const char* integrator;
    bool move;
  };
  const Case cases[] = {{"dgmpm euler fixed", "dgmpm", "euler", false},
                        {"dgmpm rk2 fixed", "dgmpm", "rk2", false},
                        {"dgmpm euler moving", "dgmpm", "euler", true},
                        {"mpm-usl flip fixed", "mpm-usl", "euler", false}};
  out << "solver throughput (one core, one particle per cell, periodic bar)\n";
  out << std::left << std::setw(22) << "case" << std::right << std::setw(12) << "particles"
      << std::setw(22) << "particle-steps/s" << '\n';
  for (const Case& c : cases)
    for (int n : particle_counts) {
      Simulation sim(bar_scene(n, c.method, c.integrator, c.move));
      const double rate = particle_steps_per_second(sim, seconds);
      out << std::left << std::setw(22) << c.label << std::right << std::setw(12) << n
          << std::setw(22) << std::scientific << std::setprecision(3) << rate << std::defaultfloat
          << '\n';
    }
}

}  // namespace dgmpm::bench
