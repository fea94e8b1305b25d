#include "bench/bench_command.hpp"

namespace dgmpm::bench {
void add_bench_command(CLI::App& app) { app.add_subcommand("bench", "Benchmarks (not yet available)"); }
}  // namespace dgmpm::bench
