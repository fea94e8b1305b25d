#pragma once
#include <CLI/CLI.hpp>

namespace dgmpm {
// Registers `dgmpm report` on the application.
void add_report_command(CLI::App& app);
}  // namespace dgmpm
