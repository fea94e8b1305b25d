#include "reports/report_command.hpp"

#include "reports/report.hpp"

#include <iostream>
#include <memory>

namespace dgmpm {

void add_report_command(CLI::App& app) {
  auto options = std::make_shared<report::ReportOptions>();
  CLI::App* cmd = app.add_subcommand(
      "report", "Run the accuracy, convergence, stability and stiff-case studies; write CSV, "
                "PNG plots and report.md");
  cmd->add_flag(
      "--quick", options->quick,
      "Coarse grids and maps (about 35 s on 2 cores in Release; the full report about 6 min)");
  cmd->add_option("--out", options->out, "Output directory")->capture_default_str();
  cmd->callback([options] {
    try {
      const report::ReportResult r = report::write_report(*options, std::cout);
      if (r.plot_status != 0) {
        std::cerr << "error: the plotting script failed (status " << r.plot_status << ")\n";
        throw CLI::RuntimeError(1);
      }
    } catch (const CLI::RuntimeError&) {
      throw;
    } catch (const std::exception& e) {
      std::cerr << "error: " << e.what() << std::endl;
      throw CLI::RuntimeError(1);
    }
  });
}

}  // namespace dgmpm
