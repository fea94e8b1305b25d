#pragma once
// The two stability criteria (docs/method.md, "Stability"), as margins: a Courant number passes
// when the margin is at most the criterion's tolerance (round-off), fails when it is above.
//   L2:        max over theta of (rho(G(theta)) - 1) / (1 - cos theta)
//              (2D: over the torus, divided by 2 - cos theta_x - cos theta_y)
//   monotone:  max over unknowns of (sum of |row of the one-step particle map| - 1)
// The L2 margin divides by 1 - cos theta so that it stays informative near theta = 0, where
// rho = 1 exactly (conservation) and, just above the limit, the growth is O(theta^2) times a
// small number: its limit at theta = 0 is minus the curvature of rho, which changes sign at a
// long-wave limit. The sign is that of max rho - 1, so passing is unchanged.

#include "stability/one_step_map.hpp"

#include <Eigen/Core>
#include <complex>
#include <limits>
#include <memory>
#include <utility>
#include <vector>

namespace dgmpm::stability {

// Round-off levels of the margins (their values near a passing C): see criteria.cpp.
constexpr double kL2MarginTolerance = 1e-9;
// 2D: eigenvalues of up to 20 x 20 symbols, and a margin divided by |theta|^2 / 2 down to
// |theta| = 0.05 (see criteria.cpp).
constexpr double kL2MarginTolerance2D = 1e-7;
// 2D L2 search: scan step in C (the scan cannot see a failing window narrower than this).
constexpr double kL2ScanStep2D = 0.05;
constexpr double kMonotoneMarginTolerance = 1e-12;

// Spectral radius of one family's G(theta) at a fixed C. Every particle value after a step is
// interpolated from its cell's nodes, so G has rank at most the cell's nodes times the family's
// components (1D: 2 per family, a closed-form 2 x 2 eigenproblem; 2D plane strain: up to 20): its
// nonzero eigenvalues are those of U^T G U, U an orthonormal basis of the range of all the
// B_{d,k} (found by SVD, not assumed).
class FamilySpectrum {
 public:
  explicit FamilySpectrum(const StencilFamily& family);
  void set_courant(double courant);
  double radius(double theta) const;                // at the last set_courant
  double radius(std::complex<double> phase) const;  // phase = e^{-i theta}
  // 2D: phases e^{-i theta_x}, e^{-i theta_y}.
  double radius(std::complex<double> phase_x, std::complex<double> phase_y) const;
  double radius(double theta_x, double theta_y) const;
  int reduced_size() const { return rank_; }

 private:
  std::vector<int> offsets_, offsets_y_;
  std::vector<std::vector<Eigen::MatrixXd>> reduced_;  // [offset][power], rank_ x rank_
  std::vector<Eigen::MatrixXd> at_courant_;            // [offset]
  int rank_ = 0;
};

// What a 2D margin was read from (a probe that can be evaluated again at another C): the margin
// at a point of the torus, the long-wave limit along a ray from the origin, or the slope off a
// neutral axis line.
enum class L2Probe { point, ray, line };

struct L2Margin {
  double value = 0.0;
  double theta = 0.0;    // where the maximum is (theta_x in 2D)
  double theta_y = 0.0;  // 2D
  int family = 0;
  L2Probe kind = L2Probe::point;  // 2D
  double phi = 0.0;               // ray: its direction (theta = 0 then)
  int line_x = 0, line_y = 0;  // line: the slope is toward (line_x, line_y) from theta - 1e-3 of it
};

// Symmetries of a 2D symbol found in the one-step map (not assumed): rho is the same at
// (theta_x, theta_y) and (-theta_x, theta_y) (mirror), and at (theta_y, theta_x) (swap). A
// layout and physics symmetric about a cell's mid-line or diagonal give them; the sweeps then
// evaluate rho once per class of equal points.
struct TorusSymmetry {
  bool mirror = false, swap = false;
};
TorusSymmetry detect_torus_symmetry(const StencilFamily& family, const CellLayout& layout,
                                    double round_off);

struct L2Growth {
  double value = 0.0;  // max rho - 1
  double theta = 0.0, theta_y = 0.0;
  int family = 0;
};

class L2Criterion {
 public:
  explicit L2Criterion(const OneStepMap& map);
  // stop_above (2D): a caller that only needs to know whether the margin exceeds it may get, when
  // it does, a value above it that is not the maximum (cheaper: refinements are skipped).
  L2Margin margin(double courant, double stop_above = std::numeric_limits<double>::infinity());
  // The margin, and in 2D also at the maximum of a growth search near the neutral lines and the
  // origin (growth(C, false)) and at the largest long-wave limit over 128 directions, which the
  // margin's scan, slopes and 16 rays can miss between their points: what a search accepts C*
  // with.
  L2Margin checked_margin(double courant,
                          double stop_above = std::numeric_limits<double>::infinity());
  // 2D: the margin on a 3 x 4 scan of the half torus (spacing pi / 2) and 4 rays, without slopes
  // (what the search scans C with; 1D: margin).
  L2Margin coarse_margin(double courant,
                         double stop_above = std::numeric_limits<double>::infinity());
  // The margin of one probe (a result of margin or coarse_margin) at C.
  double probe_margin(double courant, const L2Margin& probe);
  // A point probe moved to the nearby maximum of the margin at C (simplex); others re-evaluated.
  L2Margin sharpen(double courant, const L2Margin& probe);
  // max over families of rho(G(theta)) at C.
  double spectral_radius(double courant, double theta, double theta_y = 0.0);
  // The growth per step at C: the largest rho(G(theta)) - 1 over theta and the families, and where
  // (what a growth budget limits; see growth.cpp). Without `uniform`, only near the neutral lines
  // and the origin (2D), what the margin's own scan does not reach.
  L2Growth growth(double courant, bool uniform = true);
  const std::vector<TorusSymmetry>& symmetries() const { return symmetries_; }

 private:
  L2Margin sweep(double courant, double stop_above, bool coarse);
  struct Torus;
  std::vector<FamilySpectrum> families_;
  std::vector<TorusSymmetry> symmetries_;     // 2D, per family
  std::vector<std::shared_ptr<Torus>> tori_;  // 2D, per family: the scans' points and classes
  std::vector<L2Margin> hints_;               // per family: what exceeded the margin last time
  int dim_ = 1;
};

struct MonotoneMargin {
  double value = 0.0;
  int family = 0;
  int row = 0;  // unknown of that family (StencilFamily::particle gives the particle)
};

MonotoneMargin monotone_margin(const OneStepMap& map, double courant);

}  // namespace dgmpm::stability
