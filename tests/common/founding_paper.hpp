#pragma once
// Parameters of the founding paper's two-bar impact, shared by the solver tests.

#include <nlohmann/json.hpp>

#include <cmath>
#include <string>

namespace dgmpm::test {

inline const double E = 2e11, rho = 7800;
inline const double c = std::sqrt(E / rho), Z = std::sqrt(E * rho);
inline const double v0 = 4e9 / (2 * Z);  // sigma = 4e9 in the founding document
inline const double dx = 0.04;           // 150 cells over the two 3 m bars

// Aluminium-like second material of the bi-material bar: faster waves (c2 > c), lower impedance.
inline const double E2 = 7e10, rho2 = 2700;
inline const double c2 = std::sqrt(E2 / rho2), Z2 = std::sqrt(E2 * rho2);

// A steel bar [0, L) at velocity v hitting an aluminium bar [L, 2 L) at rest, one particle per
// cell of size dx, the interface on a cell face.
inline nlohmann::json bimaterial_bar(int cells, double v, const nlohmann::json& time) {
  const double L = cells / 2 * dx;
  const auto bar = [](const std::string& material, double lo, double hi, double velocity) {
    return nlohmann::json{{"material", material},
                          {"box", {{"min", {lo}}, {"max", {hi}}}},
                          {"particles_per_cell", 1},
                          {"velocity", {velocity}}};
  };
  return {
      {"dimension", 1},
      {"grid", {{"origin", {0.0}}, {"cell_size", {dx}}, {"cells", {cells}}}},
      {"materials",
       {{"steel", {{"young", E}, {"density", rho}}}, {"alu", {{"young", E2}, {"density", rho2}}}}},
      {"bodies", {bar("steel", 0.0, L, v), bar("alu", L, 2 * L, 0.0)}},
      {"time", time}};
}

}  // namespace dgmpm::test
