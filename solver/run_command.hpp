#pragma once
#include <CLI/CLI.hpp>

namespace dgmpm {
// Registers `dgmpm run` on the application.
void add_run_command(CLI::App& app);
}  // namespace dgmpm
