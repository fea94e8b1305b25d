#include "bench/bench_command.hpp"

#include "bench/courant_bench.hpp"
#include "bench/solver_bench.hpp"
#include "solver/run_command.hpp"

#include <algorithm>
#include <iostream>
#include <memory>
#include <stdexcept>
#include <string>

namespace dgmpm::bench {

namespace {
struct BenchArguments {
  std::vector<int> particles{100000, 1000000};
  double seconds = 2.0;
  std::vector<std::string> what{"solver", "courant"};
  int threads = 0;
  bool json = false;
  int repeats = 3;
  std::string flop_counts;
  std::string count_steps;
  int steps = 2;
  bool list_cases = false;
};
}  // namespace

void add_bench_command(CLI::App& app) {
  auto args = std::make_shared<BenchArguments>();
  CLI::App* cmd = app.add_subcommand(
      "bench", "Benchmarks: solver throughput (speed is measured here, not in tests)");
  cmd->add_option("--particles", args->particles, "Particle counts for the solver benchmark")
      ->delimiter(',')
      ->check(CLI::PositiveNumber);
  cmd->add_option("--seconds", args->seconds,
                  "Time spent per case (and per auto time step cost measurement)")
      ->check(CLI::PositiveNumber);
  CLI::Option* what =
      cmd->add_option(
             "--what", args->what,
             "Benchmarks to run: solver, courant (default both), plate (2D; give "
             "--particles 10000,100000,1000000), courant-2d (2D query costs, 3 runs each), "
             "scaling (2D plate over the ranks of `mpirun -np N`; JSON lines; "
             "scripts/scaling.sh runs it)")
          ->delimiter(',')
          ->check(CLI::IsMember({"solver", "courant", "plate", "courant-2d", "scaling"}));
  add_threads_option(*cmd, args->threads);
  CLI::Option* json =
      cmd->add_flag(
             "--json", args->json,
             "The speed goals as one JSON object (one core unless said; the largest of "
             "--particles, default 1e6): particle-steps/s min and median of --repeats runs of "
             "--seconds each, heap bytes per particle, bytes per particle-step by count, the "
             "triad bandwidth and the fraction of its bound, two threads against one")
          ->excludes(what);
  cmd->add_option("--repeats", args->repeats, "Runs per case for --json (min and median)")
      ->check(CLI::Range(1, 100))
      ->needs(json);
  cmd->add_option("--flop-counts", args->flop_counts,
                  "With --json: each case's roofline from these flops per particle-step "
                  "(the JSON bench/count_flops.py writes)")
      ->check(CLI::ExistingFile)
      ->needs(json);
  CLI::Option* count =
      cmd->add_option("--count-steps", args->count_steps,
                      "Take --steps steps of this --json case (--particles, the largest) and "
                      "nothing else: what bench/count_flops.py counts under callgrind")
          ->excludes(json)
          ->excludes(what);
  cmd->add_option("--steps", args->steps, "Steps for --count-steps")
      ->check(CLI::Range(1, 1000000))
      ->needs(count);
  cmd->add_flag("--cases", args->list_cases, "Print the --json cases' names, one per line")
      ->excludes(json)
      ->excludes(what)
      ->excludes(count);
  cmd->callback([args] {
    apply_threads(args->threads);
    const int particles = *std::max_element(args->particles.begin(), args->particles.end());
    if (args->list_cases) {
      for (const auto& name : goal_case_names()) std::cout << name << '\n';
      return;
    }
    try {
      if (!args->count_steps.empty()) {
        run_counted_steps(args->count_steps, particles, args->steps);
        return;
      }
      if (args->json) {
        run_goals_benchmark(std::cout, particles, args->seconds, args->repeats, args->flop_counts);
        return;
      }
    } catch (const std::runtime_error& e) {  // a bad --count-steps or --flop-counts
      std::cerr << "dgmpm bench: " << e.what() << '\n';
      throw CLI::RuntimeError(2);
    }
    for (const auto& w : args->what) {
      if (w == "solver") run_solver_benchmark(std::cout, args->particles, args->seconds);
      if (w == "courant") run_courant_benchmark(std::cout);
      if (w == "plate") run_plate_benchmark(std::cout, args->particles, args->seconds);
      if (w == "courant-2d") run_courant_2d_benchmark(std::cout, 3);
      if (w == "scaling") run_scaling_benchmark(std::cout, args->particles, args->seconds);
    }
  });
}

}  // namespace dgmpm::bench
