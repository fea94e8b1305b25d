// dgmpm: the user's entry point. Each subcommand registers itself from its own part of the tree.
#include "bench/bench_command.hpp"
#include "reports/report_command.hpp"
#include "solver/communicator.hpp"
#include "solver/installation.hpp"
#include "solver/run_command.hpp"
#include "solver/scene_spectrum.hpp"
#include "stability/courant_command.hpp"

#include <CLI/CLI.hpp>

#include <cstdlib>
#include <string>

#ifdef DGMPM_MPI
#include <mpi_communicator.hpp>
#endif

namespace {

int run_app(int argc, char** argv) {
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

}  // namespace

int main(int argc, char** argv) {
#ifdef DGMPM_MPI
  // Under mpirun (its launcher sets these), `dgmpm run` distributes the scene over the ranks;
  // started directly, the binary is serial and MPI stays uninitialised.
  if (std::getenv("OMPI_COMM_WORLD_SIZE") || std::getenv("PMIX_RANK") || std::getenv("PMI_SIZE")) {
    MPI_Init(&argc, &argv);
    int code = 0;
    {
      dgmpm::distributed::MpiCommunicator world(MPI_COMM_WORLD);
      dgmpm::set_launched_ranks(&world);
      code = run_app(argc, argv);
      dgmpm::set_launched_ranks(nullptr);
    }
    MPI_Finalize();
    return code;
  }
#endif
  return run_app(argc, argv);
}
