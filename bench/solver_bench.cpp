#include "bench/solver_bench.hpp"

#include "bench/roofline.hpp"

#include "solver/communicator.hpp"
#include "solver/problem.hpp"
#include "solver/simulation.hpp"
#include "solver/time_step_control.hpp"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <dgmpm/discretisation.hpp>
#include <iomanip>
#include <iostream>
#include <limits>
#include <malloc.h>
#include <map>
#include <nlohmann/json.hpp>
#include <omp.h>
#include <stdexcept>
#include <string>
#include <string_view>
#include <utility>

namespace dgmpm::bench {

namespace {

// A periodic steel bar moving rigidly: every cell holds `ppc` particles, nothing leaves.
// `auto_courant`: "courant": "auto" with the l2 criterion instead of a fixed 0.5.
scene::Scene bar_scene(int particles, const std::string& method, const std::string& integrator,
                       bool move, bool auto_courant = false, int ppc = 1) {
  const int cells = particles / ppc;
  const double length = 1.0;
  nlohmann::json time = {{"end", 1.0}, {"integrator", integrator}, {"courant", 0.5}};
  if (auto_courant) {
    time["courant"] = "auto";
    time["criterion"] = "l2";
  }
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
                           {"particles_per_cell", ppc},
                           {"velocity", {1.0}}}}},
                        {"time", time},
                        {"particles_move", move}};
  return scene::parse_scene(doc, "bench");
}

// Calls per second of `call`: best of several timed batches (the minimum time is the least
// disturbed by other load), after one warm-up call (buffers allocated, caches filled).
template <class Call>
double best_calls_per_second(Call&& call, double seconds) {
  using clock = std::chrono::steady_clock;
  call();
  int batch = 1;
  double best = 0.0, spent = 0.0;
  while (spent < seconds) {
    const auto t0 = clock::now();
    for (int k = 0; k < batch; ++k) call();
    const double s = std::chrono::duration<double>(clock::now() - t0).count();
    spent += s;
    best = std::max(best, batch / s);
    if (s < 0.05) batch *= 2;
  }
  return best;
}

// With "courant": "auto" the step length changes as particles move: each step takes the one the
// previous step computed.
double particle_steps_per_second(BarSimulation& sim, double seconds) {
  const bool fresh_dt = sim.scene().time.courant_auto;
  const double dt = sim.stable_time_step();
  const double steps_per_second =
      best_calls_per_second([&] { sim.step(fresh_dt ? sim.stable_time_step() : dt); }, seconds);
  return steps_per_second * static_cast<double>(sim.particles().size());
}

// The moving auto run, kept for the time-step cost table.
struct AutoRun {
  int particles = 0;
  int ppc = 1;
  double particle_steps_per_second = 0;
  long steps = 0;
  int layouts_analysed = 0;
  Particles<1, ElasticBar::n_comp> final_particles;
};

// Per particle: the operator rebuild of a moving step, the automatic time step with a warm cache
// (both on the particles as the moving auto run left them) and the run's full step.
void print_time_step_cost(std::ostream& out, const std::vector<AutoRun>& runs, double seconds) {
  out << "auto time step cost: ns per particle for rebuild, dt (warm cache), full step\n";
  out << std::right << std::setw(5) << "ppc" << std::setw(12) << "particles" << std::setw(12)
      << "rebuild" << std::setw(18) << "dt (warm cache)" << std::setw(12) << "full step"
      << std::setw(10) << "steps" << std::setw(20) << "layouts analysed" << '\n';
  for (const AutoRun& run : runs) {
    const scene::Scene scene = bar_scene(run.particles, "dgmpm", "euler", true, true, run.ppc);
    BarProblem problem = make_bar_problem(scene);
    problem.particles = run.final_particles;
    Discretisation<ElasticBar> disc;
    const double n = static_cast<double>(problem.particles.size());
    const double rebuilds = best_calls_per_second(
        [&] { disc.build(problem.grid, problem.particles, problem.materials); }, seconds);
    TimeStepControl<ElasticBar> control(scene, problem.max_wave_speed());
    double dt = 0;
    const double dts = best_calls_per_second(
        [&] { dt = control.time_step(problem.grid, disc, problem.particles, problem.materials); },
        seconds);
    const auto ns = [n](double per_second) { return 1e9 / (per_second * n); };
    out << std::setw(5) << run.ppc << std::setw(12) << run.particles << std::fixed
        << std::setprecision(2) << std::setw(12) << ns(rebuilds) << std::setw(18) << ns(dts)
        << std::setw(12) << 1e9 / run.particle_steps_per_second << std::defaultfloat
        << std::setw(10) << run.steps << std::setw(20) << run.layouts_analysed << '\n';
  }
  out << "(rebuild and dt on the particles as the moving auto run left them; full step and\n"
         " layouts analysed (cache misses, about 0.03-0.8 ms each) from that run)\n";
}

}  // namespace

void run_solver_benchmark(std::ostream& out, const std::vector<int>& particle_counts,
                          double seconds) {
  struct Case {
    const char* label;
    const char* method;
    const char* integrator;
    bool move;
    bool auto_courant;
    int ppc = 1;
  };
  const Case cases[] = {{"dgmpm euler fixed", "dgmpm", "euler", false, false},
                        {"dgmpm rk2 fixed", "dgmpm", "rk2", false, false},
                        {"dgmpm euler moving", "dgmpm", "euler", true, false},
                        {"dgmpm euler moving auto", "dgmpm", "euler", true, true},
                        {"... same, 2 ppc", "dgmpm", "euler", true, true, 2},
                        {"mpm-usl flip fixed", "mpm-usl", "euler", false, false}};
  std::vector<AutoRun> auto_runs;
  out << "solver throughput (" << omp_get_max_threads() << " thread(s) for grids of "
      << DGOperator<ElasticBar>::kThreadedCells
      << " cells or more; one particle per cell unless said, "
         "periodic bar)\n";
  out << std::left << std::setw(26) << "case" << std::right << std::setw(12) << "particles"
      << std::setw(22) << "particle-steps/s" << '\n';
  for (const Case& c : cases)
    for (int n : particle_counts) {
      BarSimulation sim(bar_scene(n, c.method, c.integrator, c.move, c.auto_courant, c.ppc));
      const double rate = particle_steps_per_second(sim, seconds);
      out << std::left << std::setw(26) << c.label << std::right << std::setw(12) << n
          << std::setw(22) << std::scientific << std::setprecision(3) << rate << std::defaultfloat
          << '\n';
      if (c.move && c.auto_courant)
        auto_runs.push_back({n, c.ppc, rate, sim.steps(),
                             sim.time_step_control()->layouts_analysed(), sim.particles()});
    }
  if (!auto_runs.empty()) print_time_step_cost(out, auto_runs, seconds);
}

namespace {

// The founding paper's plate (4 m x 3 m, -2e8 Pa on the lower metre of the left edge, other
// edges free) with about `particles` particles: square-ish cells, ppc per axis 1 or 2.
// How the plate's steel yields: not at all; elastoplastic (scenes/plate_plastic.json's material:
// only the particles the loading wave has reached return); or viscoplastic with a relaxation far
// slower than the run and an initial stress three times the yield stress, so that every particle
// returns at every step: with rate exponent 1 (every_particle: Perzyna's closed form) or the
// viscoplastic strip's 4.37 (every_particle_newton: Newton's iteration with pow, the worst case).
enum class Yielding { none, plastic, every_particle, every_particle_newton };

// `hyperelastic` names a finite-strain law for the steel (the same moduli) instead.
scene::Scene plate_scene(int particles, int ppc_axis, const std::string& flux,
                         const std::string& integrator, const std::string& method = "dgmpm",
                         Yielding yielding = Yielding::none, const std::string& hyperelastic = "") {
  const double per_cell = ppc_axis * ppc_axis;
  const int nx =
      std::max(1, static_cast<int>(std::lround(std::sqrt(particles / per_cell * 4 / 3))));
  const int ny = std::max(1, static_cast<int>(std::lround(nx * 0.75)));
  nlohmann::json doc = {
      {"dimension", 2},
      {"method", method},
      {"grid", {{"origin", {0.0, 0.0}}, {"cell_size", {4.0 / nx, 3.0 / ny}}, {"cells", {nx, ny}}}},
      {"materials", {{"steel", {{"young", 2e11}, {"poisson", 0.3}, {"density", 7800}}}}},
      {"bodies",
       {{{"material", "steel"},
         {"box", {{"min", {0.0, 0.0}}, {"max", {4.0, 3.0}}}},
         {"particles_per_cell", {ppc_axis, ppc_axis}}}}},
      {"boundaries",
       {{"xmin", {{{"type", "traction"}, {"value", {-2e8, 0.0}}, {"range", {0.0, 1.0}}}}}}},
      {"time", {{"end", 1.0}, {"integrator", integrator}, {"courant", 0.5}}}};
  if (method == "dgmpm") doc["flux"] = flux;
  auto& steel = doc["materials"]["steel"];
  if (yielding != Yielding::none) {
    steel["model"] = "elastoplastic";
    steel["yield_stress"] = 1e8;  // half the load
    steel["isotropic_hardening"] = 2e9;
  }
  if (yielding == Yielding::every_particle || yielding == Yielding::every_particle_newton) {
    steel["model"] = "elasto_viscoplastic";
    steel["relaxation_time"] = 1.0;
    steel["rate_exponent"] = yielding == Yielding::every_particle ? 1.0 : 4.37;
    doc["bodies"][0]["stress"] = {-3e8, 0.0, 0.0};
  }
  if (!hyperelastic.empty()) steel["model"] = hyperelastic;
  return scene::parse_scene(doc, "bench plate");
}

// Bytes the heap holds now (glibc: arena bytes in use plus mmapped blocks).
double heap_bytes() {
  const struct mallinfo2 m = mallinfo2();
  return static_cast<double>(m.uordblks + m.hblkhd);
}

}  // namespace

void run_scaling_benchmark(std::ostream& out, const std::vector<int>& particle_counts,
                           double seconds) {
  Communicator* ranks = launched_ranks();
  const int size = ranks ? ranks->size() : 1;
  // Every rank takes the slowest rank's figures (the step ends when the last rank's does).
  const auto largest = [&](double v) { return ranks ? -ranks->min(-v) : v; };
  const auto total = [&](double v) {
    if (ranks) ranks->sum({&v, 1});
    return v;
  };
  using clock = std::chrono::steady_clock;
  for (int n : particle_counts) {
    PlaneStrainSimulation sim(plate_scene(n, 1, "dcu", "euler"), size > 1 ? ranks : nullptr);
    const double dt = sim.stable_time_step();
    sim.step(dt);  // buffers allocated
    const auto* halo = sim.halo();
    const auto traffic_before = halo ? halo->traffic() : decltype(halo->traffic()){};
    long steps = 0;
    double best = std::numeric_limits<double>::infinity(), spent = 0;
    for (int batch = 1; spent < seconds;) {
      if (ranks) ranks->barrier();
      const auto t0 = clock::now();
      for (int k = 0; k < batch; ++k) sim.step(dt);
      const double s = largest(std::chrono::duration<double>(clock::now() - t0).count());
      steps += batch;
      spent += s;
      best = std::min(best, s / batch);
      if (s < 0.05) batch *= 2;
    }
    const double owned = sim.owned_particles(), particles = total(owned);
    nlohmann::json j = {{"ranks", size},
                        {"threads", omp_get_max_threads()},
                        {"particles", particles},
                        {"cells", sim.num_cells()},
                        {"steps", steps},
                        {"seconds_per_step", best},
                        {"particle_steps_per_second", particles / best},
                        {"imbalance", largest(owned) * size / particles}};
    if (halo) {
      const auto& t = halo->traffic();
      const double exchanges = static_cast<double>(t.exchanges - traffic_before.exchanges);
      j["halo_seconds_per_step"] = largest((t.seconds - traffic_before.seconds) / exchanges);
      j["halo_bytes_sent_per_step"] =
          largest((t.bytes_sent - traffic_before.bytes_sent) / exchanges);
      j["messages_per_step"] = largest(halo->subdomain().partners().size());
      j["ghost_particles"] = largest(sim.particles().size() - sim.owned_particles());
    }
    if (!ranks || ranks->rank() == 0) out << j.dump() << std::endl;
  }
}

void run_plate_benchmark(std::ostream& out, const std::vector<int>& particle_counts,
                         double seconds) {
  out << "2D plate throughput (" << omp_get_max_threads() << " thread(s) for grids of "
      << DGOperator<ElasticBar>::kThreadedCells
      << " cells or more; DGMPM, Courant 0.5) and heap bytes per "
         "particle\n";
  out << std::left << std::setw(6) << "flux" << std::setw(7) << "time" << std::setw(5) << "ppc"
      << std::right << std::setw(12) << "particles" << std::setw(20) << "particle-steps/s"
      << std::setw(16) << "bytes/particle" << '\n';
  for (int ppc_axis : {1, 2})
    for (const char* flux : {"dcu", "ctu"})
      for (const char* integrator : {"euler", "rk2"})
        for (int n : particle_counts) {
          const scene::Scene scene = plate_scene(n, ppc_axis, flux, integrator);
          const double before = heap_bytes();
          PlaneStrainSimulation sim(scene);
          const double dt = sim.stable_time_step();
          sim.step(dt);  // every buffer allocated
          const double bytes = (heap_bytes() - before) / sim.particles().size();
          const double rate =
              best_calls_per_second([&] { sim.step(dt); }, seconds) * sim.particles().size();
          out << std::left << std::setw(6) << flux << std::setw(7) << integrator << std::setw(5)
              << ppc_axis * ppc_axis << std::right << std::setw(12) << sim.particles().size()
              << std::setw(20) << std::scientific << std::setprecision(3) << rate
              << std::defaultfloat << std::setw(16) << std::fixed << std::setprecision(0) << bytes
              << std::defaultfloat << '\n';
        }
}

namespace {

// STREAM's triad a = b + s c on arrays far larger than the caches, on this thread: bytes per
// second (24 per element, STREAM's count), best of `runs`.
double triad_bytes_per_second(int runs) {
  const std::size_t n = std::size_t{1} << 23;  // 64 MB per array
  std::vector<double> a(n, 0.0), b(n, 1.0), c(n, 2.0);
  double best = 0.0;
  for (int r = 0; r < runs; ++r) {
    const auto t0 = std::chrono::steady_clock::now();
    const double scalar = 3.0 + r;
    for (std::size_t i = 0; i < n; ++i) a[i] = b[i] + scalar * c[i];
    const double s = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
    best = std::max(best, 24.0 * static_cast<double>(n) / s);
    b[r % n] = a[(r * 7919) % n];  // keep the stores live
  }
  return best;
}

// The bytes a particle-step cannot avoid moving to and from memory, by count: the particle's
// state read and written, its mass, and its shape values at its cell's nodes (per-cell data such
// as the pseudo-stiffness is left out: it could be recomputed from the particles); moving
// particles add their position read and written and the shape values written by the rebuild;
// MPM reads the position (shape functions computed on the fly), the mass and reads and writes
// the state and the volume.
struct Traffic {
  int dim, ncomp;
  bool move, mpm;
  double bytes() const {
    const int npc = 1 << dim;
    if (mpm) return 8.0 * (2 * ncomp + 1 + 2 + dim);
    double b = 8.0 * (2 * ncomp + 1 + npc);
    if (move) b += 8.0 * (2 * dim + npc);
    return b;
  }
};

struct Rates {
  std::vector<double> runs;  // particle-steps per second
  double min() const { return *std::min_element(runs.begin(), runs.end()); }
  double median() const {
    std::vector<double> v = runs;
    std::sort(v.begin(), v.end());
    return v[v.size() / 2];
  }
};

// One timed step: at `dt`, or at a time step chosen for it ("courant": "auto").
template <class Physics>
void goal_step(Simulation<Physics>& sim, double dt) {
  sim.step(sim.scene().time.courant_auto ? sim.stable_time_step() : dt);
}

template <class Physics>
Rates time_steps(Simulation<Physics>& sim, int repeats, double seconds) {
  using clock = std::chrono::steady_clock;
  const double dt = sim.stable_time_step();
  const auto step = [&] { goal_step(sim, dt); };
  step();  // warm: every buffer allocated
  Rates rates;
  const double n = sim.particles().size();
  for (int r = 0; r < repeats; ++r) {
    long steps = 0;
    const auto t0 = clock::now();
    double spent = 0;
    while (spent < seconds) {
      step();
      ++steps;
      spent = std::chrono::duration<double>(clock::now() - t0).count();
    }
    rates.runs.push_back(static_cast<double>(steps) * n / spent);
  }
  return rates;
}

struct GoalCase {
  std::string name;
  scene::Scene scene;
  Traffic traffic;
};

// Share of the particles that have yielded (plastic_strain > 0; 0 for elastic physics): how many of
// the timed particle-steps can have run a return, the rest only the yield check.
template <class Physics>
double yielded_share(const Simulation<Physics>& sim) {
  const auto& names = Physics::internal_names;
  const auto row = std::find_if(names.begin(), names.end(), [](const char* name) {
    return std::string_view(name) == "plastic_strain";
  });
  if (row == names.end()) return 0.0;
  const auto& p = sim.particles();
  int yielded = 0;
  for (int i = 0; i < p.size(); ++i) yielded += p.internal(row - names.begin(), i) > 0 ? 1 : 0;
  return static_cast<double>(yielded) / p.size();
}

nlohmann::json measure_case(const GoalCase& c, int repeats, double seconds, double triad) {
  return with_physics(c.scene, [&](auto physics) {
    using Physics = typename decltype(physics)::type;
    const double before = heap_bytes();
    Simulation<Physics> sim(c.scene);
    sim.step(sim.stable_time_step());  // every buffer allocated
    const double n = sim.particles().size();
    const double resident = (heap_bytes() - before) / n;
    const Rates rates = time_steps(sim, repeats, seconds);
    const double bytes = c.traffic.bytes();
    const double bound = triad / bytes;
    return nlohmann::json{
        {"case", c.name},
        {"particles", sim.particles().size()},
        {"threads", omp_get_max_threads()},
        {"particle_steps_per_second",
         {{"min", rates.min()}, {"median", rates.median()}, {"runs", rates.runs}}},
        {"resident_bytes_per_particle", resident},
        {"bytes_per_particle_step", bytes},
        {"bound_particle_steps_per_second", bound},
        {"fraction_of_bound", rates.median() / bound},
        {"yielded_share", yielded_share(sim)}};
  });
}

// Particle states after `steps` steps of the scene on `threads` threads.
Eigen::MatrixXd states_after(const scene::Scene& scene, int threads, int steps) {
  omp_set_num_threads(threads);
  return with_physics(scene, [&](auto physics) {
    using Physics = typename decltype(physics)::type;
    Simulation<Physics> sim(scene);
    const double dt = sim.stable_time_step();
    for (int k = 0; k < steps; ++k) sim.step(dt);
    return Eigen::MatrixXd(sim.particles().state);
  });
}

// The goal cases at `particles` particles.
std::vector<GoalCase> goal_cases(int particles) {
  return {
      {"1D DGMPM Euler", bar_scene(particles, "dgmpm", "euler", false), {1, 2, false, false}},
      {"1D DGMPM RK2", bar_scene(particles, "dgmpm", "rk2", false), {1, 2, false, false}},
      {"1D moving, auto dt, 2 ppc",
       bar_scene(particles, "dgmpm", "euler", true, true, 2),
       {1, 2, true, false}},
      {"2D DGMPM DCU Euler, 1 ppc",
       plate_scene(particles, 1, "dcu", "euler"),
       {2, 5, false, false}},
      {"2D DGMPM CTU RK2, 1 ppc", plate_scene(particles, 1, "ctu", "rk2"), {2, 5, false, false}},
      {"2D DGMPM 4 ppc (DCU Euler)",
       plate_scene(particles, 2, "dcu", "euler"),
       {2, 5, false, false}},
      {"2D MPM USL, 1 ppc",
       plate_scene(particles, 1, "dcu", "euler", "mpm-usl"),
       {2, 5, false, true}},
      {"2D DGMPM CTU Euler, 1 ppc",
       plate_scene(particles, 1, "ctu", "euler"),
       {2, 5, false, false}},
      {"2D DGMPM CTU Euler, 4 ppc",
       plate_scene(particles, 2, "ctu", "euler"),
       {2, 5, false, false}},
      {"2D plastic DCU Euler, 1 ppc",
       plate_scene(particles, 1, "dcu", "euler", "dgmpm", Yielding::plastic),
       {2, 5, false, false}},
      {"2D plastic DCU Euler, 4 ppc",
       plate_scene(particles, 2, "dcu", "euler", "dgmpm", Yielding::plastic),
       {2, 5, false, false}},
      {"2D plastic CTU Euler, 1 ppc",
       plate_scene(particles, 1, "ctu", "euler", "dgmpm", Yielding::plastic),
       {2, 5, false, false}},
      {"2D plastic CTU Euler, 4 ppc",
       plate_scene(particles, 2, "ctu", "euler", "dgmpm", Yielding::plastic),
       {2, 5, false, false}},
      {"2D every particle returns, DCU Euler, 1 ppc",
       plate_scene(particles, 1, "dcu", "euler", "dgmpm", Yielding::every_particle),
       {2, 5, false, false}},
      {"2D every particle returns, CTU Euler, 1 ppc",
       plate_scene(particles, 1, "ctu", "euler", "dgmpm", Yielding::every_particle),
       {2, 5, false, false}},
      {"2D every particle returns, n = 4.37, DCU Euler, 1 ppc",
       plate_scene(particles, 1, "dcu", "euler", "dgmpm", Yielding::every_particle_newton),
       {2, 5, false, false}},
      // Finite strain: (F, v) and the displacement read and written; the step's speeds from every
      // particle's acoustic tensors, every step.
      {"2D finite strain neo-Hookean DCU Euler, 1 ppc",
       plate_scene(particles, 1, "dcu", "euler", "dgmpm", Yielding::none, "neo_hookean"),
       {2, 8, false, false}},
      {"2D finite strain SVK DCU Euler, 1 ppc",
       plate_scene(particles, 1, "dcu", "euler", "dgmpm", Yielding::none, "saint_venant_kirchhoff"),
       {2, 8, false, false}}};
}

// `steps` goal steps, the only code count_flops.py's callgrind counts (--toggle-collect).
template <class Physics>
[[gnu::noinline]] void counted_steps(Simulation<Physics>& sim, double dt, int steps) {
  for (int k = 0; k < steps; ++k) goal_step(sim, dt);
}

const GoalCase& find_case(const std::vector<GoalCase>& cases, const std::string& name) {
  for (const GoalCase& c : cases)
    if (c.name == name) return c;
  std::string allowed;
  for (const GoalCase& c : cases) allowed += (allowed.empty() ? "\"" : ", \"") + c.name + "\"";
  throw std::runtime_error("--count-steps: no goal case \"" + name + "\"; allowed: " + allowed);
}

}  // namespace

std::vector<std::string> goal_case_names() {
  std::vector<std::string> names;
  for (const GoalCase& c : goal_cases(1000)) names.push_back(c.name);
  return names;
}

void run_counted_steps(const std::string& name, int particles, int steps) {
  const std::vector<GoalCase> cases = goal_cases(particles);
  const GoalCase& c = find_case(cases, name);
  with_physics(c.scene, [&](auto physics) {
    using Physics = typename decltype(physics)::type;
    Simulation<Physics> sim(c.scene);
    const double dt = sim.stable_time_step();
    goal_step(sim, dt);  // warm, as the timed runs are: every buffer allocated, caches filled
    counted_steps(sim, dt, steps);
    std::cout << nlohmann::json{{"case", name},
                                {"particles", sim.particles().size()},
                                {"steps", steps}}
                     .dump()
              << '\n';
  });
}

void run_goals_benchmark(std::ostream& out, int particles, double seconds, int repeats,
                         const std::string& flop_counts) {
  const std::map<std::string, StepCount> counts =
      flop_counts.empty() ? std::map<std::string, StepCount>{} : read_step_counts(flop_counts);
  const int threads = omp_get_max_threads();
  omp_set_num_threads(1);  // the goals are for one core unless said
  const double triad = triad_bytes_per_second(5);
  const ArithmeticPeak peak = measure_arithmetic_peak(5);
  const std::vector<GoalCase> cases = goal_cases(particles);
  for (const GoalCase& c : cases)
    if (!counts.empty() && !counts.count(c.name))
      throw std::runtime_error("--flop-counts: \"" + flop_counts + "\" has no case \"" + c.name +
                               "\" (count them again: bench/count_flops.py)");
  // What a plastic step costs: each plastic plate against the same elastic plate, measured in
  // this run (medians' ratio; the traffic counted is the elastic step's).
  const std::vector<std::pair<std::string, std::string>> plastic_pairs{
      {"2D plastic DCU Euler, 1 ppc", "2D DGMPM DCU Euler, 1 ppc"},
      {"2D plastic DCU Euler, 4 ppc", "2D DGMPM 4 ppc (DCU Euler)"},
      {"2D plastic CTU Euler, 1 ppc", "2D DGMPM CTU Euler, 1 ppc"},
      {"2D plastic CTU Euler, 4 ppc", "2D DGMPM CTU Euler, 4 ppc"},
      {"2D every particle returns, DCU Euler, 1 ppc", "2D DGMPM DCU Euler, 1 ppc"},
      {"2D every particle returns, CTU Euler, 1 ppc", "2D DGMPM CTU Euler, 1 ppc"},
      {"2D every particle returns, n = 4.37, DCU Euler, 1 ppc", "2D DGMPM DCU Euler, 1 ppc"}};
  nlohmann::json report;
  report["triad_bytes_per_second"] = triad;
  report["repeats"] = repeats;
  report["seconds_per_repeat"] = seconds;
  report["arithmetic_peak_flops_per_second"] = {{"build", peak.build}, {"fma", peak.fma}};
  if (!flop_counts.empty()) report["flop_counts"] = flop_counts;
  for (const GoalCase& c : cases) {
    nlohmann::json result = measure_case(c, repeats, seconds, triad);
    if (!counts.empty()) {
      const auto count = counts.find(c.name);
      result["roofline"] =
          roofline(count->second, result["particle_steps_per_second"]["median"].get<double>(),
                   c.traffic.bytes(), peak, triad);
    }
    report["cases"].push_back(std::move(result));
  }
  const auto median_of = [&](const std::string& name) {
    for (const auto& c : report["cases"])
      if (c["case"] == name) return c["particle_steps_per_second"]["median"].get<double>();
    throw std::logic_error("bench: no case " + name);
  };
  for (const auto& [plastic, elastic] : plastic_pairs)
    report["plastic_step_cost"].push_back({{"case", plastic},
                                           {"elastic", elastic},
                                           {"cost", median_of(elastic) / median_of(plastic)}});
  // What a finite-strain step costs against the small-strain one, the same way.
  for (const char* finite :
       {"2D finite strain neo-Hookean DCU Euler, 1 ppc", "2D finite strain SVK DCU Euler, 1 ppc"})
    report["finite_strain_step_cost"].push_back(
        {{"case", finite},
         {"small_strain", "2D DGMPM DCU Euler, 1 ppc"},
         {"cost", median_of("2D DGMPM DCU Euler, 1 ppc") / median_of(finite)}});
  // Two threads against one, every case: rates and identical states.
  if (threads >= 2)
    for (std::size_t k = 0; k < cases.size(); ++k) {
      omp_set_num_threads(2);
      nlohmann::json two = measure_case(cases[k], repeats, seconds, 2 * triad);
      const double one = report["cases"][k]["particle_steps_per_second"]["median"];
      const bool identical =
          states_after(cases[k].scene, 1, 5) == states_after(cases[k].scene, 2, 5);
      report["two_threads"].push_back(
          {{"case", cases[k].name},
           {"particle_steps_per_second", two["particle_steps_per_second"]},
           {"speed_up", two["particle_steps_per_second"]["median"].get<double>() / one},
           {"bit_identical", identical}});
    }
  omp_set_num_threads(threads);
  out << report.dump(2) << '\n';
}

}  // namespace dgmpm::bench
