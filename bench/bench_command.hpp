#pragma once
#include <CLI/CLI.hpp>

namespace dgmpm::bench {
// Registers `dgmpm bench` on the application.
void add_bench_command(CLI::App& app);
}  // namespace dgmpm::bench
