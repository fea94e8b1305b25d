#include "stability/courant_command.hpp"

namespace dgmpm::stability {
// Placeholder until the stability analysis lands.
void add_courant_command(CLI::App& app) { app.add_subcommand("courant", "Admissible Courant number (not yet available)"); }
}  // namespace dgmpm::stability
