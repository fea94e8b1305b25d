#pragma once
// Scenes with most of what a step must handle: loads, void cells, two materials (the threads and
// fused-step tests step them two ways and compare).

#include <nlohmann/json.hpp>

#include <string>
#include <vector>

namespace dgmpm::test {

// Two bars (steel at 2 particles per cell, a soft one at 1) covering part of a grid of `cells`
// cells of size h from x = -0.1 (void cells at both ends), a traction table on the left end, a
// free right end.
inline nlohmann::json loaded_bar(int cells, double h, const std::string& integrator, bool move) {
  return {{"dimension", 1},
          {"grid", {{"origin", {-0.1}}, {"cell_size", {h}}, {"cells", {cells}}}},
          {"materials",
           {{"steel", {{"young", 2e11}, {"density", 7800}}},
            {"soft", {{"young", 2e9}, {"density", 1000}}}}},
          {"bodies",
           {{{"material", "steel"},
             {"box", {{"min", {0.0}}, {"max", {3.0}}}},
             {"velocity", {10.0}},
             {"particles_per_cell", 2}},
            {{"material", "soft"},
             {"box", {{"min", {3.0}}, {"max", {5.5}}}},
             {"velocity", {-10.0}},
             {"particles_per_cell", 1}}}},
          {"boundaries",
           {{"xmin", {{"type", "traction"}, {"value", {{0.0, 0.0}, {1e-4, -1e8}, {1.0, -1e8}}}}},
            {"xmax", {{"type", "free"}}}}},
          {"time", {{"end", 1.0}, {"integrator", integrator}, {"courant", 0.4}}},
          {"particles_move", move}};
}

// A steel plate with a soft inclusion on a grid of nx x ny square cells of size h (the bodies
// cover part of it), `ppc` x `ppc` particles per cell in the steel, a normal and shear traction
// on the lower metre of the left edge, a roller bottom edge.
inline nlohmann::json loaded_plate(int nx, int ny, double h, int ppc, const std::string& flux,
                                   const std::string& integrator, bool move) {
  return {{"dimension", 2},
          {"flux", flux},
          {"grid", {{"origin", {0.0, 0.0}}, {"cell_size", {h, h}}, {"cells", {nx, ny}}}},
          {"materials",
           {{"steel", {{"young", 2e11}, {"poisson", 0.3}, {"density", 7800}}},
            {"soft", {{"young", 2e10}, {"poisson", 0.25}, {"density", 2000}}}}},
          {"bodies",
           {{{"material", "steel"},
             {"box", {{"min", {0.0, 0.0}}, {"max", {3.5, 2.5}}}},
             {"velocity", {1.0, -2.0}},
             {"particles_per_cell", {ppc, ppc}}},
            {{"material", "soft"},
             {"box", {{"min", {3.5, 0.0}}, {"max", {3.9, 2.5}}}},
             {"particles_per_cell", {1, 1}}}}},
          {"boundaries",
           {{"xmin", {{{"type", "traction"}, {"value", {-2e8, 1e7}}, {"range", {0.0, 1.0}}}}},
            {"ymin", {{"type", "roller"}}}}},
          {"time", {{"end", 1.0}, {"integrator", integrator}, {"courant", 0.4}}},
          {"particles_move", move}};
}

// The plate's bodies stretched to the top of its grid, the soft one to its right side (so that
// periodic wraps link occupied cells).
inline nlohmann::json filled(nlohmann::json doc) {
  const auto& grid = doc["grid"];
  const double top = grid["origin"][1].get<double>() +
                     grid["cells"][1].get<double>() * grid["cell_size"][1].get<double>();
  const double right = grid["origin"][0].get<double>() +
                       grid["cells"][0].get<double>() * grid["cell_size"][0].get<double>();
  for (auto& body : doc["bodies"]) body["box"]["max"][1] = top;
  doc["bodies"].back()["box"]["max"][0] = right;
  return doc;
}

// The scene with the grid periodic along the axes marked true, their boundaries removed.
inline nlohmann::json periodic(nlohmann::json doc, const std::vector<bool>& axes) {
  const char* sides[3][2] = {{"xmin", "xmax"}, {"ymin", "ymax"}, {"zmin", "zmax"}};
  for (std::size_t a = 0; a < axes.size(); ++a)
    if (axes[a] && doc.contains("boundaries"))
      for (const char* side : sides[a]) doc["boundaries"].erase(side);
  doc["grid"]["periodic"] = axes.size() == 1 ? nlohmann::json(bool(axes[0])) : nlohmann::json(axes);
  return doc;
}

// The scene with its steel yielding (the loaded plate's traction is above its yield stress).
inline nlohmann::json plastic(nlohmann::json doc) {
  auto& steel = doc["materials"]["steel"];
  steel["model"] = "elastoplastic";
  steel["yield_stress"] = 3e7;
  steel["isotropic_hardening"] = 1e9;
  steel["kinematic_hardening"] = 5e9;
  return doc;
}

// The scene with every material neo-Hookean (finite strain, total Lagrangian: the displacement is
// the internal variable).
inline nlohmann::json finite(nlohmann::json doc) {
  for (auto& [name, material] : doc["materials"].items()) material["model"] = "neo_hookean";
  return doc;
}

}  // namespace dgmpm::test
