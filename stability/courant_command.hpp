#pragma once
#include <CLI/CLI.hpp>

namespace dgmpm::stability {
// Registers `dgmpm courant` on the application.
void add_courant_command(CLI::App& app);
}  // namespace dgmpm::stability
