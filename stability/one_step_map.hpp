#pragma once
// The particle-to-particle one-step map of lib's stepper on a periodic grid of identical cells
// (docs/method.md, "Stability"): u^{n+1}(e) = sum_d B_d u^n(e - d), and
// G(theta) = sum_d B_d e^{-i d . theta}, d an offset in cells (1D, or 2D: (d_x, d_y)).
//
// B_d is never derived by hand: lib's step is applied to unit particle vectors on a small
// periodic grid and the responses are read off; the offsets it reaches are detected. The map is
// a polynomial in the Courant number C (degree 1 for Euler, 2 for RK2, twice that for CTU, whose
// operator scales its transverse corrections with dt), so B_d(C) = sum_k C^k B_{d,k}: the
// coefficients come from exact Lagrange interpolation of degree + 1 applications of the step,
// checked against one more application, and later evaluations at any C cost a few flops.

#include "stability/layout.hpp"
#include "stability/options.hpp"

#include <Eigen/Core>
#include <complex>
#include <string>
#include <vector>

namespace dgmpm::stability {

// A set of unknowns per cell that the map does not couple to the others. Advection has one
// family; the elastic bar, in characteristic variables w = sigma -+ Z v, has two (one per wave
// direction), exactly decoupled because the Godunov flux is upwind on each characteristic. The
// 2D elastic system does not decouple: one family of all 5 N unknowns.
struct StencilFamily {
  std::string direction;       // "+x" or "-x": where this family's waves travel ("both" if coupled)
  int size = 0;                // unknowns per cell
  std::vector<int> offsets;    // along x
  std::vector<int> offsets_y;  // along y, same length (0 in 1D)
  std::vector<std::vector<Eigen::MatrixXd>> coefficients;  // [offset index][power of C]
  std::vector<int> particle;                               // layout particle of each unknown

  Eigen::MatrixXd block(std::size_t offset_index, double courant) const;
};

struct OneStepMap {
  CellLayout layout;
  AnalysisSetting setting;
  int degree = 1;
  std::vector<StencilFamily> families;
  // Round-off level of the coefficients: about 1e-15 / the smallest nodal mass share.
  double round_off = 0.0;
  // What round-off can add to a margin computed from this map (criteria tolerances start here).
  double round_off_level() const;
};

// Throws std::invalid_argument for an invalid layout (or one whose dimension is not the
// setting's), std::logic_error if lib's step is not the expected polynomial in dt or reaches
// further than the analysis window (+-3 cells).
OneStepMap build_one_step_map(const CellLayout& layout, const AnalysisSetting& setting);
// 1D.
OneStepMap build_one_step_map(const CellLayout& layout, TimeScheme scheme, Model model);

// G(theta_x, theta_y) of one family at Courant number C.
Eigen::MatrixXcd amplification_matrix(const StencilFamily& family, double courant, double theta,
                                      double theta_y = 0.0);

}  // namespace dgmpm::stability
