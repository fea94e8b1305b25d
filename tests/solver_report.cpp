// `dgmpm report --quick`: every figure and table is produced and its numbers hold.
#define BOOST_TEST_MODULE report
#include <boost/test/unit_test.hpp>

#include "common/scratch.hpp"

#include "reports/report.hpp"

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <iomanip>
#include <limits>
#include <map>
#include <sstream>
#include <string>
#include <vector>

using namespace dgmpm::report;
namespace fs = std::filesystem;

namespace {

struct QuickReport {
  fs::path dir;
  ReportResult result;
  std::string markdown;
  QuickReport() : dir(dgmpm::test::scratch() / "report") {
    std::ostringstream log;
    result = write_report({true, dir.string(), true}, log);
    BOOST_TEST_MESSAGE(log.str());
    std::ifstream in(dir / "report.md");
    markdown.assign(std::istreambuf_iterator<char>(in), {});
  }
};

const QuickReport& report() {
  static const QuickReport r;  // one quick run serves every test case
  return r;
}

}  // namespace

BOOST_AUTO_TEST_CASE(every_file_is_written_and_not_empty) {
  const QuickReport& r = report();
  BOOST_TEST(r.result.plot_status == 0);
  std::vector<std::string> names = report_csv_files();
  for (const auto& png : report_png_files()) names.push_back(png);
  for (const auto& name : names) {
    BOOST_TEST_CONTEXT(name) {
      BOOST_TEST(fs::exists(r.dir / name));
      BOOST_TEST((fs::exists(r.dir / name) && fs::file_size(r.dir / name) > 0));
      BOOST_TEST(r.markdown.find(name) != std::string::npos);  // referenced by the report
    }
  }
  BOOST_TEST(!r.markdown.empty());
  for (const auto& entry : fs::directory_iterator(r.dir))  // no temporary left behind
    BOOST_TEST(entry.path().filename().string().find("tmp") == std::string::npos, entry.path());
}

BOOST_AUTO_TEST_CASE(header_states_where_and_how) {
  const std::string& md = report().markdown;
  for (const char* key : {"| dgmpm |", "| commit |", "| build type |", "| CPU |", "| cores |",
                          "| threads |", "| load at the start |", "| date |"})
    BOOST_TEST(md.find(key) != std::string::npos, key);
}

// The automatic step is Courant 1 where C* = 1 (one particle per cell; RK2): exact transport.
BOOST_AUTO_TEST_CASE(dgmpm_automatic_step_is_exact_on_the_two_bars_where_c_star_is_one) {
  int found = 0;
  for (const RunRow& r : report().result.runs)
    if (r.problem == "two_bar" &&
        (r.label == "DGMPM Euler 1ppc auto" || r.label == "DGMPM RK2 4ppc auto")) {
      ++found;
      BOOST_TEST(r.stable);
      BOOST_TEST(r.l2_error < 1e-10, r.label << ", " << r.cells << " cells: " << r.l2_error);
    }
  BOOST_TEST(found >= 6);
}

// 2D: every plane-wave run is stable with an error that falls with the cell size, and the
// stability section holds the known exact limits.
BOOST_AUTO_TEST_CASE(two_dimensional_sections) {
  const auto& res = report().result;
  BOOST_TEST_REQUIRE(!res.plane_waves.empty());
  for (const RunRow& r : res.plane_waves) {
    BOOST_TEST(r.stable, r.label << ", " << r.cells << " cells: " << r.failure);
    BOOST_TEST(r.l2_error < 1.0, r.label);
  }
  for (const OrderFit& f : res.plane_orders) BOOST_TEST(f.order > 0.5, f.label << ": " << f.order);
  const std::string& md = report().markdown;
  for (const char* s :
       {"## 5. The 2D plate", "## 6. 2D plane waves", "## 7. 2D stability",
        "| elastic | l2 | dcu | rk2 | 1.0000 |", "| elastic | l2 | ctu | euler | 1.0000 |"})
    BOOST_TEST(md.find(s) != std::string::npos, s);
}

// best_per_budget.csv: for each study (the two 1D ones and the 2D plane wave) and budget, the
// least error among the stable runs within the budget, recomputed here from the runs.
BOOST_AUTO_TEST_CASE(best_per_budget_is_the_least_error_within_each_budget) {
  const ReportResult& res = report().result;
  std::ifstream in(report().dir / "best_per_budget.csv");
  std::string line;
  std::getline(in, line);
  BOOST_TEST(line == "problem,budget_seconds,label,cells,wall_seconds,l2_error");
  std::map<std::string, int> rows;
  while (std::getline(in, line)) {
    std::vector<std::string> field;
    std::stringstream fields(line);
    for (std::string f; std::getline(fields, f, ',');) field.push_back(f);
    BOOST_TEST_REQUIRE(field.size() == 6u, line);
    const std::string& problem = field[0];
    const double budget = std::stod(field[1]), error = std::stod(field[5]);
    const auto& runs = problem == "plane_wave_p_30deg" ? res.plane_waves : res.runs;
    double least = std::numeric_limits<double>::infinity();
    for (const RunRow& r : runs)
      if (r.problem == problem && r.stable && r.wall_seconds <= budget)
        least = std::min(least, r.l2_error);
    BOOST_TEST_REQUIRE(std::isfinite(least), line << ": no stable run within the budget");
    BOOST_TEST(std::abs(error - least) <= 1e-9 * least, line << ": least " << least);  // 10 digits
    BOOST_TEST(std::stod(field[4]) <= budget, line);
    ++rows[problem];
  }
  for (const char* problem : {"two_bar", "smooth_pulse", "plane_wave_p_30deg"})
    BOOST_TEST(rows[problem] >= 1, problem);
  BOOST_TEST(report().markdown.find("| plane_wave_p_30deg | ") != std::string::npos);
}

BOOST_AUTO_TEST_CASE(dgmpm_errors_decrease_under_refinement_on_the_smooth_pulse) {
  std::map<std::string, std::vector<const RunRow*>> by_method;
  for (const RunRow& r : report().result.runs)
    if (r.problem == "smooth_pulse" && r.label.rfind("DGMPM", 0) == 0)
      by_method[r.label].push_back(&r);
  BOOST_TEST(by_method.size() == 12u);
  for (const auto& [label, rows] : by_method) {
    BOOST_TEST_CONTEXT(label) {
      BOOST_TEST(rows.size() >= 3u);
      for (std::size_t k = 1; k < rows.size(); ++k) {
        BOOST_TEST(rows[k]->stable);
        BOOST_TEST(rows[k]->h < rows[k - 1]->h);
        BOOST_TEST(rows[k]->l2_error < rows[k - 1]->l2_error, rows[k]->cells << " cells");
      }
    }
  }
}

BOOST_AUTO_TEST_CASE(every_fitted_order_is_finite_and_printed) {
  const QuickReport& r = report();
  int fitted = 0;
  for (const OrderFit& f : r.result.orders) {
    BOOST_TEST_CONTEXT(f.problem << ", " << f.label) {
      // Only DGMPM at round-off on the two bars may go without an order.
      if (!f.note.empty()) {
        BOOST_TEST(f.note == "round-off error on every grid");
        BOOST_TEST(f.problem == "two_bar");
        BOOST_TEST(r.markdown.find("n/a: " + f.note) != std::string::npos);
        continue;
      }
      ++fitted;
      BOOST_TEST(std::isfinite(f.order));
      std::ostringstream printed;
      printed << "| " << f.label;
      BOOST_TEST(r.markdown.find(printed.str()) != std::string::npos);
      std::ostringstream order;
      order << std::fixed << std::setprecision(2) << f.order << " (" << f.points << " grids)";
      BOOST_TEST(r.markdown.find(order.str()) != std::string::npos, order.str());
    }
  }
  // Every smooth-pulse method has an order.
  BOOST_TEST(fitted >= 18);
}

BOOST_AUTO_TEST_CASE(stiff_cases_are_tabulated) {
  const QuickReport& r = report();
  const auto& stiff = r.result.stiff;
  BOOST_TEST(stiff.size() >= 10u);
  for (const RunRow& row : stiff)
    BOOST_TEST(r.markdown.find("| " + row.label + " |") != std::string::npos, row.label);
  // Automatic steps on the plain layouts hold; whether every extreme case does is what the table
  // reports, not a property of the report.
  BOOST_TEST(stiff.front().stable);
  BOOST_TEST(stiff.front().max_error < 1e-10);
  // The contrast row runs above the layout's admissible Courant number, and its note says so.
  BOOST_TEST(!stiff.back().stable);
  BOOST_TEST(stiff.back().warning.find("is above the admissible") != std::string::npos);
  BOOST_TEST(r.markdown.find("| Courant number 1 is above the admissible 0.686141 |") !=
             std::string::npos);
  // Moving 2 ppc particles pile up: with the paper's formulation the note names the first
  // over-full cell; the consistent one preserves constant states there and has no such note.
  for (const RunRow& row : stiff)
    if (row.label.find("moving particles, 2 ppc") != std::string::npos)
      BOOST_TEST((row.warning.find("times a full cell's mass") != std::string::npos) ==
                     (row.label.find("paper's") != std::string::npos),
                 row.label);
}

namespace {

// Rows of a report CSV as maps from column name to text.
std::vector<std::map<std::string, std::string>> read_csv(const fs::path& path) {
  std::ifstream in(path);
  std::string line;
  std::getline(in, line);
  std::vector<std::string> header;
  std::stringstream hs(line);
  for (std::string cell; std::getline(hs, cell, ',');) header.push_back(cell);
  std::vector<std::map<std::string, std::string>> rows;
  while (std::getline(in, line)) {
    std::stringstream ls(line);
    std::map<std::string, std::string> row;
    std::size_t k = 0;
    for (std::string cell; std::getline(ls, cell, ',') && k < header.size(); ++k)
      row[header[k]] = cell;
    rows.push_back(row);
  }
  return rows;
}

}  // namespace

// Section 8 against the thesis's exact values (written here, independently of the report):
// the uniaxial-strain wave's plateau |sigma_xx| = 1.2610 GPa and |eps_p_xx| = 2.0308e-3, MPM's
// plastic strain overshooting DGMPM's at the impact plane (as the thesis reports), the energy of
// every DGMPM run below its initial value, and the Perzyna precursor's last jump near the exact
// 0.8014 GPa (slow relaxation, first order at 200 cells) and Y_H = 700 MPa (stiff).
BOOST_AUTO_TEST_CASE(the_solids_that_yield_section_holds_the_exact_plateau) {
  const auto& r = report();
  BOOST_TEST(r.markdown.find("## 8. Solids that yield") != std::string::npos);
  std::map<std::string, std::map<std::string, std::string>> plateau;
  for (const auto& row : read_csv(r.dir / "plastic_wave_plateaus.csv"))
    plateau[row.at("label")] = row;
  const auto value = [&](const std::string& label, const std::string& column) {
    return std::abs(std::stod(plateau.at(label).at(column)));
  };
  BOOST_TEST(value("DGMPM 1 ppc", "sigma_xx_plateau") == 1.2610e9,
             boost::test_tools::tolerance(1e-3));
  BOOST_TEST(value("DGMPM 1 ppc", "eps_p_xx_plateau") == 2.0308e-3,
             boost::test_tools::tolerance(5e-3));
  BOOST_TEST(value("DGMPM 2 ppc", "sigma_xx_plateau") == 1.2610e9,
             boost::test_tools::tolerance(2e-3));
  for (const char* mpm : {"MPM USL 2 ppc", "MPM USF 2 ppc"})
    BOOST_TEST(value(mpm, "eps_p_xx_peak") > 1.2 * value("DGMPM 1 ppc", "eps_p_xx_peak"), mpm);
  int dgmpm_runs = 0;
  for (const auto& row : read_csv(r.dir / "plastic_wave_runs.csv"))
    if (row.at("label").rfind("DGMPM", 0) == 0) {
      ++dgmpm_runs;
      BOOST_TEST(std::stod(row.at("energy_change")) <= 1e-12, row.at("label")
                                                                  << " " << row.at("cells"));
      BOOST_TEST(std::stod(row.at("l2_error_sigma_xx")) < 0.2);
    }
  BOOST_TEST(dgmpm_runs == 6);
  std::map<double, double> last_jump;  // tau -> |jump| at the last time read
  for (const auto& row : read_csv(r.dir / "viscoplastic_precursor.csv"))
    if (row.at("kind") == "jump")
      last_jump[std::stod(row.at("tau"))] = -std::stod(row.at("sigma_xx"));
  BOOST_TEST_REQUIRE(last_jump.size() == 2u);
  // 200 cells in quick mode: 7% above; first order (400 cells 3.8%, 800 cells 1.6%).
  BOOST_TEST(last_jump.rbegin()->second > 0.8014e9);
  BOOST_TEST(last_jump.rbegin()->second == 0.8014e9, boost::test_tools::tolerance(0.09));
  BOOST_TEST(last_jump.begin()->second == 7e8, boost::test_tools::tolerance(0.03));
}

// Section 9: DGMPM's automatic step keeps the SVK shocks within 1e-3 of their plateaus with no
// overshoot worth the name and the energy below the initial energy plus the work; the MPM
// baseline overshoots by over 10% (the thesis: 21% and 27%); at Courant 1 the speeds after a
// 20 GPa step give about 1.11 (docs/method.md), and the fan converges.
BOOST_AUTO_TEST_CASE(the_finite_strain_section_holds_the_exact_plateaus) {
  const auto& r = report();
  BOOST_TEST(r.markdown.find("## 9. Finite strain") != std::string::npos);
  int checked = 0;
  for (const auto& row : read_csv(r.dir / "finite_strain_runs.csv")) {
    const std::string& label = row.at("label");
    const std::string what = row.at("case") + ", " + label;
    if (row.at("case") == "svk_fan") continue;
    const double overshoot = std::stod(row.at("overshoot"));
    const double plateau = std::stod(row.at("plateau_error"));
    if (label == "DGMPM auto") {
      ++checked;
      BOOST_TEST(std::abs(overshoot) < 1e-3, what);
      BOOST_TEST(std::abs(plateau) < 1e-3, what);
      BOOST_TEST(std::stod(row.at("energy_excess_max")) < 0.0, what);
      BOOST_TEST(std::stod(row.at("courant_start_max")) <= 0.9 * (1 + 1e-12), what);
    } else if (label.rfind("MPM", 0) == 0) {
      ++checked;
      BOOST_TEST(overshoot > 0.1, what);
      BOOST_TEST(std::abs(plateau) < 5e-3, what);
    } else if (row.at("case") == "svk_20gpa") {
      ++checked;
      BOOST_TEST(std::stod(row.at("courant_after_max")) == 1.11,
                 boost::test_tools::tolerance(0.01));
    }
  }
  BOOST_TEST(checked == 3 * 3 + 1);
  std::map<std::string, std::vector<double>> fan;
  for (const auto& row : read_csv(r.dir / "finite_strain_fan.csv"))
    fan[row.at("label")].push_back(std::stod(row.at("l1_error_f")));
  BOOST_TEST_REQUIRE(fan.size() == 2u);
  for (const auto& [label, e] : fan) BOOST_TEST(e.back() < 0.6 * e.front(), label);
}
