// dgmpm: the user's entry point. Each subcommand registers itself from its own part of the tree.
#include "bench/bench_command.hpp"
#include "reports/report_command.hpp"
#include "solver/installation.hpp"
#include "solver/run_command.hpp"
#include "solver/scene_spectrum.hpp"
#include "stability/courant_command.hpp"

#include <CLI/CLI.hpp>

#include <string>

int main(int argc, char** argv) {
  CLI::App app{"dgmpm: Discontinuous Galerkin Material Point Method solver and stability analysis"};
  app.set_version_flag("--version", std::string("dgmpm ") + dgmpm::version());
  app.require_subcommand(1);
  dgmpm::add_run_command(app);
  dgmpm::stability::add_courant_command(app);
  dgmpm::stability::set_scene_analysis(dgmpm::scene_courant_command);
  dgmpm::bench::add_bench_command(app);
  dgmpm::add_report_command(app);
  CLI11_PARSE(app, argc, argv);
  return 0;
}
