#pragma once
// `dgmpm report`, finite strain (1D, total Lagrangian, uniaxial strain): the Saint Venant-Kirchhoff
// half-space pulled by 2 and 20 GPa (shocks) and pushed by 20 GPa (a fan), and the neo-Hookean
// halves meeting at +-100 m/s, DGMPM and the MPM baseline against their exact solutions: the
// overshoot at the shock beside the thesis's, plateau errors, the Courant number measured with the
// speeds after each step, the energy balance, the fan's convergence and the profiles.
#include <iosfwd>
#include <string>
#include <vector>

namespace dgmpm::report {

struct FiniteStrainSection {
  std::string markdown;            // the section, headed "## 9."
  std::vector<std::string> files;  // CSV written
  double seconds = 0;              // runs (plots not included)
};

FiniteStrainSection finite_strain_section(const std::string& dir, bool quick, bool plots,
                                          int& plot_status, std::ostream& log);
std::vector<std::string> finite_strain_csv_files();
std::vector<std::string> finite_strain_png_files();

}  // namespace dgmpm::report
