#pragma once
// `dgmpm report`: runs the accuracy, convergence, stability and stiff-case studies with the
// current build and writes raw CSV, PNG plots (through reports/plot.py) and report.md.

#include "reports/cases.hpp"

#include <iosfwd>
#include <string>
#include <vector>

namespace dgmpm::report {

struct ReportOptions {
  bool quick = false;  // coarse grids and maps: every figure and table in seconds
  std::string out = "reports/output";
  bool plots = true;  // run the plotting script
};

// A fitted convergence order: log(error) = intercept + order log(h) over `points` grids.
struct OrderFit {
  std::string problem, label;
  int points = 0;
  double order = 0, intercept = 0;
  std::string note;  // why no fit (round-off everywhere, too few stable grids); empty when fitted
};

struct ReportResult {
  std::vector<RunRow> runs;            // accuracy study, both problems
  std::vector<OrderFit> orders;        // one per problem and method
  std::vector<RunRow> stiff;           // stiff and extreme cases
  std::vector<RunRow> plane_waves;     // 2D accuracy study
  std::vector<OrderFit> plane_orders;  // one per 2D method
  std::vector<std::string> files;
  int plot_status = -1;  // exit status of the plotting script (0: every PNG written)
  double wall_seconds = 0;
};

// Throws std::runtime_error when a file cannot be written. Progress goes to `log`.
ReportResult write_report(const ReportOptions& options, std::ostream& log);

// Files the report always produces, relative to its directory.
std::vector<std::string> report_csv_files();
std::vector<std::string> report_png_files();

}  // namespace dgmpm::report
