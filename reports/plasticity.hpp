#pragma once
// `dgmpm report`, solids that yield: the thesis's uniaxial-strain plane wave (DGMPM with one and
// two particles per cell, MPM USL and USF) against its exact solution (profiles at three times,
// plateau and peak of the plastic strain, error against run time), the Perzyna precursor's decay
// for a slow and a stiff relaxation, and the plastic zone of the founding plate loaded at twice
// its yield stress.
#include <iosfwd>
#include <string>
#include <vector>

namespace dgmpm::report {

struct PlasticitySection {
  std::string markdown;            // the section, headed "## 8."
  std::vector<std::string> files;  // CSV and the plate's particle files written
  double seconds = 0;              // runs (plots not included)
};

// Runs the studies into `dir` (quick: coarse grids) and plots them when `plots`; the plotting
// status is added to `plot_status` when it is still 0.
PlasticitySection plasticity_section(const std::string& dir, bool quick, bool plots,
                                     int& plot_status, std::ostream& log);
std::vector<std::string> plasticity_csv_files();
std::vector<std::string> plasticity_png_files();

}  // namespace dgmpm::report
