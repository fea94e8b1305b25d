#pragma once
#include <CLI/CLI.hpp>

namespace dgmpm {
// Registers `dgmpm run` on the application.
void add_run_command(CLI::App& app);

// `--threads N` of a subcommand (run, bench): OpenMP threads for the step on large grids and the
// stability analysis; 0 (not given) leaves OpenMP's default. apply_threads sets it.
CLI::Option* add_threads_option(CLI::App& cmd, int& threads);
void apply_threads(int threads);
}  // namespace dgmpm
