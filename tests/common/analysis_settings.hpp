#pragma once
// 2D analysis settings and layouts the stability tests share.

#include "stability/layout.hpp"
#include "stability/options.hpp"

#include <utility>
#include <vector>

namespace dgmpm::test {

inline stability::AnalysisSetting advection(double a, double b, FluxScheme flux, TimeScheme time) {
  stability::AnalysisSetting s;
  s.dim = 2;
  s.model = stability::Model::advection;
  s.speed_x = a;
  s.speed_y = b;
  s.flux = flux;
  s.time = time;
  return s;
}

inline stability::AnalysisSetting elastic(double nu, FluxScheme flux, TimeScheme time) {
  stability::AnalysisSetting s;
  s.dim = 2;
  s.model = stability::Model::elastic;
  s.poisson = nu;
  s.flux = flux;
  s.time = time;
  return s;
}

// The same with the founding paper's formulation (pseudo-stiffness summed over the particles,
// RK2's stages undamped).
inline stability::AnalysisSetting paper(stability::AnalysisSetting s) {
  s.formulation = Formulation::paper;
  return s;
}

inline stability::CellLayout points(std::vector<double> xy, std::vector<double> masses = {}) {
  return stability::CellLayout{std::move(xy), std::move(masses), 2};
}

inline const FluxScheme dcu = FluxScheme::dcu, ctu = FluxScheme::ctu;
inline const TimeScheme euler = TimeScheme::euler, rk2 = TimeScheme::rk2;

}  // namespace dgmpm::test
