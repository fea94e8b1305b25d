#include "solver/run_command.hpp"

#include "solver/checkpoint.hpp"
#include "solver/communicator.hpp"
#include "solver/installation.hpp"
#include "solver/output.hpp"
#include "solver/simulation.hpp"

#include <chrono>
#include <cmath>
#include <csignal>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <iostream>
#include <memory>
#include <omp.h>
#include <thread>

namespace dgmpm {

namespace {

// SIGTERM, SIGINT and SIGHUP ask a run to stop after its current step and write its record.
volatile std::sig_atomic_t stop_requested = 0;
extern "C" void request_stop(int signal) {
  stop_requested = signal;
}

struct RunArguments {
  std::string scene;  // default: the two-bar impact shipped with dgmpm (share/dgmpm/scenes)
  std::string out;
  bool json = false;
  bool overwrite = false;
  bool scene_given = false;
  std::string checkpoint_every;  // N (steps) or Ts (simulated seconds)
  int checkpoint_keep = 0;
  std::string restart;
  int threads = 0;             // 0: OpenMP's default (OMP_NUM_THREADS, else the cores)
  double progress_every = 10;  // batch progress lines (0: none)
};

// "--checkpoint-every": N steps, or T simulated seconds written "Ts" (e.g. 2e-4s).
void parse_checkpoint_every(const std::string& text, RunOptions& options) {
  const auto refuse = [&] {
    return scene::SceneError("--checkpoint-every: value \"" + text +
                             "\"; allowed: a positive whole number of steps (e.g. 1000) or a "
                             "positive time in simulated seconds ending in s (e.g. 2e-4s)");
  };
  if (text.empty()) throw refuse();
  std::size_t used = 0;
  try {
    if (text.back() == 's') {
      const std::string number = text.substr(0, text.size() - 1);
      const double t = std::stod(number, &used);
      if (used != number.size() || !(t > 0) || !std::isfinite(t)) throw refuse();
      options.checkpoint_seconds = t;
    } else {
      const long n = std::stol(text, &used);
      if (used != text.size() || n <= 0) throw refuse();
      options.checkpoint_steps = n;
    }
  } catch (const std::logic_error&) {  // std::stod / std::stol: not a number, out of range
    throw refuse();
  }
}

void print_human(const scene::Scene& scene, const SimulationBase& sim, const RunSummary& s) {
  std::printf(
      "%s: %dD, %s, %s%s%s, %d particles, %d cells\n", scene.source.c_str(), scene.dimension,
      scene::to_string(scene.method), scene::to_string(scene.time.integrator),
      scene.dimension > 1 && scene.method == scene::Method::dgmpm ? ", " : "",
      scene.dimension > 1 && scene.method == scene::Method::dgmpm ? to_string(scene.flux) : "",
      sim.num_particles(), sim.num_cells());
  std::printf("steps %ld, final time %.9g s, dt %.6g to %.6g s, wall %.3f s (set-up %.3f s, "
              "steps %.3f s)\n",
              s.steps, s.final_time, s.dt_min, s.dt_max, s.wall_seconds, s.setup_seconds,
              s.stepping_seconds);
  if (scene.time.courant_auto) {
    std::printf("automatic time step (%s", scene::to_string(scene.time.criterion));
    if (scene.time.criterion == scene::Criterion::budget)
      std::printf(" %g over the run", scene.time.growth_budget);
    std::printf(", safety %g): %d layouts analysed, %.3f s choosing steps\n", scene.time.safety,
                s.layouts_analysed, s.time_step_seconds);
  }
  const char* unit = energy_unit(scene.dimension);
  if (s.energy_initial > 0)
    std::printf("energy (%s): initial %.12g, final %.12g, relative change %.3e\n", unit,
                s.energy_initial, s.energy_final,
                (s.energy_final - s.energy_initial) / s.energy_initial);
  else  // a body at rest: the loads' work below is the reference
    std::printf("energy (%s): initial %.12g, final %.12g\n", unit, s.energy_initial,
                s.energy_final);
  if (s.energy_stored && s.energy_dissipated)  // materials that yield: the final energy's parts
    std::printf("  of which stored by hardening %.12g, dissipated by plastic flow %.12g (the "
                "rest kinetic and elastic)\n",
                *s.energy_stored, *s.energy_dissipated);
  if (std::isfinite(s.boundary_work) && s.boundary_work != 0)  // MPM: NaN, not measured
    std::printf("work of the boundary loads %.12g %s; energy - initial energy - work %.6g %s\n",
                s.boundary_work, unit, s.energy_final - s.energy_initial - s.boundary_work, unit);
  if (s.stress_errors) {
    std::printf("relative error against the exact solution at t = %.9g s:\n", s.final_time);
    std::printf("  %-9s %12s %12s %12s\n", "field", "L1", "L2", "max");
    const auto row = [](const char* name, const ErrorNorms& e) {
      std::printf("  %-9s %12.4e %12.4e %12.4e\n", name, e.l1, e.l2, e.max);
    };
    row("stress", *s.stress_errors);
    row("velocity", *s.velocity_errors);
  }
  for (const auto& f : s.files) std::printf("wrote %s\n", f.c_str());
}

int run(const RunArguments& args) {
  Communicator* const run_ranks = launched_ranks();
  const bool distributed = run_ranks && run_ranks->size() > 1;
  const bool root = !distributed || run_ranks->rank() == 0;
  // On several ranks an error on one leaves the others waiting: it ends them all. Who says it:
  // the rank that met it; rank 0 for a scene's error (every rank meets it); another rank for
  // RankStopped. A rank that leaves it to another waits, then speaks only if still alive (the
  // error was its alone).
  enum class Speaker { self, root, another };
  const auto fail = [&](const char* what, int code, Speaker speaker) {
    if (!distributed) {
      std::cerr << "error: " << what << std::endl;
      return code;
    }
    if ((speaker == Speaker::root && !root) || speaker == Speaker::another)
      std::this_thread::sleep_for(std::chrono::seconds(2));
    {
      const std::string line = "error (rank " + std::to_string(run_ranks->rank()) + " of " +
                               std::to_string(run_ranks->size()) + "): " + what + "\n";
      std::fputs(line.c_str(), stderr);  // one write: lines of ranks do not interleave
      std::fflush(stderr);
    }
    run_ranks->abort(code);  // does not return
    return code;
  };
  std::unique_ptr<SimulationBase> owned;
  // From here on a signal stops the run at its next step (during set-up: at its first).
  output::set_stop_handler(request_stop);
  try {
    // Several ranks share the node's cores: one thread each unless asked (threads of ranks
    // sharing a core spin at the sweeps' barriers and slow the run many times over).
    if (distributed && args.threads == 0 && !std::getenv("OMP_NUM_THREADS"))
      apply_threads(1);
    else
      apply_threads(args.threads);
    RunOptions options;
    if (!args.checkpoint_every.empty()) parse_checkpoint_every(args.checkpoint_every, options);
    options.checkpoint_keep = args.checkpoint_keep;
    if (args.checkpoint_keep > 0 && args.checkpoint_every.empty())
      throw scene::SceneError("--checkpoint-keep: value " + std::to_string(args.checkpoint_keep) +
                              " keeps the newest checkpoints, but none are written; allowed: "
                              "with --checkpoint-every");
    std::string scene_path = args.scene;
    if (!args.restart.empty() && !args.scene_given) {  // the scene the checkpoint was written by
      scene_path = checkpoint::read(args.restart).header.value("scene_source", std::string());
    } else if (!args.scene_given) {
      // The shipped default scene writes where the user is, not into the installed data.
      scene_path = data_file("scenes/two_bar_impact.json");
      if (args.out.empty()) options.output_directory = "out/two_bar_impact";
    }
    const scene::Scene scene = scene::load_scene(scene_path);
    owned = make_simulation(scene, distributed ? run_ranks : nullptr);
    SimulationBase& sim = *owned;
    if (!args.restart.empty()) sim.restore(args.restart);
    if (!args.out.empty()) {
      options.output_directory = args.out;
    } else if (!args.restart.empty()) {  // a restart continues where its checkpoint is
      const std::string here = std::filesystem::path(args.restart).parent_path().string();
      options.output_directory = here.empty() ? "." : here;
    }
    options.progress = args.progress_every > 0;
    options.progress_every = args.progress_every;
    options.overwrite = args.overwrite;
    options.stop = &stop_requested;
    if (root)
      for (const auto& w : sim.warnings()) std::cerr << "warning: " << w << std::endl;
    const double first_checkpoint =
        options.checkpoint_seconds * (std::floor(sim.time() / options.checkpoint_seconds) + 1);
    if (root && options.checkpoint_seconds > 0 && first_checkpoint >= scene.time.end)
      std::cerr << "warning: --checkpoint-every " << args.checkpoint_every
                << ": the first checkpoint would be at t = " << first_checkpoint
                << " s, not before the end time " << scene.time.end << " s: none is written"
                << std::endl;
    const RunSummary summary = sim.run(options);
    // Interrupted: the shell's convention for a process a signal ended, after the record.
    const int code = summary.status == "interrupted" ? 128 + static_cast<int>(stop_requested) : 0;
    if (!root) return code;
    if (args.json) {
      std::cout << summary.to_json().dump(2) << std::endl;  // as summary.json
    } else {
      print_human(scene, sim, summary);
      if (code) std::cerr << "interrupted: " << summary.reason << std::endl;
    }
    return code;
  } catch (const scene::SceneError& e) {
    return fail(e.what(), 2, Speaker::root);
  } catch (const RankStopped& e) {
    return fail(e.what(), 1, Speaker::another);
  } catch (const std::exception& e) {
    // --json: the failed run's summary (status, reason, what it reached) on stdout as well.
    if (args.json && root && owned && owned->last_summary())
      std::cout << owned->last_summary()->to_json().dump(2) << std::endl;
    return fail(e.what(), 1, Speaker::self);
  }
}

}  // namespace

CLI::Option* add_threads_option(CLI::App& cmd, int& threads) {
  return cmd
      .add_option("--threads", threads,
                  "Threads for the step on large grids and for the stability analysis (default: "
                  "OMP_NUM_THREADS, else the cores); results do not depend on it")
      ->check(CLI::Range(1, 1024));
}

void apply_threads(int threads) {
  if (threads > 0) omp_set_num_threads(threads);
}

void add_run_command(CLI::App& app) {
  auto args = std::make_shared<RunArguments>();
  CLI::App* cmd = app.add_subcommand("run", "Run a scene: DGMPM or MPM time loop, outputs, errors");
  cmd->add_option("scene", args->scene, "Scene file (JSON); default: the two-bar impact")
      ->check(CLI::ExistingFile);
  cmd->add_option("--out", args->out, "Output directory (overrides the scene's output.directory)");
  cmd->add_flag("--json", args->json, "Print one JSON object with the run's summary");
  cmd->add_flag("--overwrite", args->overwrite,
                "Replace another scene's outputs in the output directory");
  cmd->add_option("--checkpoint-every", args->checkpoint_every,
                  "Write a checkpoint into the output directory every N steps (N) or every T "
                  "simulated seconds (Ts, e.g. 2e-4s)");
  cmd->add_option("--checkpoint-keep", args->checkpoint_keep,
                  "Keep only the newest K checkpoints (default: all)")
      ->check(CLI::PositiveNumber);
  cmd->add_option("--progress-every", args->progress_every,
                  "When stderr is not a terminal (a batch job's log), a progress line every S "
                  "seconds (default 10; 0: none, on a terminal too)")
      ->check(CLI::NonNegativeNumber);
  add_threads_option(*cmd, args->threads);
  cmd->add_option("--restart", args->restart,
                  "Continue from a checkpoint (the scene defaults to the one that wrote it)")
      ->check(CLI::ExistingFile);
  cmd->callback([args, cmd] {
    args->scene_given = cmd->count("scene") > 0;
    const int code = run(*args);
    if (code != 0) throw CLI::RuntimeError(code);
  });
}

}  // namespace dgmpm
