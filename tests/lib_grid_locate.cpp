// Grid::locate's contract, checked from positions built independently of it: a point inside
// lies in the cell whose box holds it, at local coordinates that rebuild it; a point on a face
// (to round-off) belongs to the cell on its plus side with xi = 0 exactly, the grid's upper
// boundary to the last cell with xi = 1; outside a non-periodic grid (or not finite) is -1;
// periodic axes wrap whole periods; a window gives the full grid's coordinates to the bit.
#define BOOST_TEST_MODULE grid_locate
#include <boost/test/unit_test.hpp>

#include <dgmpm/grid.hpp>

#include <algorithm>
#include <cmath>
#include <limits>
#include <random>

using namespace dgmpm;

namespace {

Grid<2> plate(bool periodic_x) {
  Grid<2> g;
  g.origin << -0.3, 1.7;
  g.cell_size << 0.1, 0.37;
  g.cells = {13, 7};
  g.periodic = {periodic_x, false};
  return g;
}

double position(const Grid<2>& g, int l, double cells) {
  return g.origin[l] + cells * g.cell_size[l];
}

}  // namespace

BOOST_AUTO_TEST_CASE(a_point_inside_lies_in_its_cell_at_coordinates_that_rebuild_it) {
  const Grid<2> g = plate(false);
  std::mt19937 gen(7);
  std::uniform_real_distribution<double> u(0.001, 0.999);
  for (int n = 0; n < 20000; ++n) {
    const Grid<2>::Index k = {static_cast<int>(gen() % 13), static_cast<int>(gen() % 7)};
    Grid<2>::Vec x, xi = Grid<2>::Vec::Zero();
    for (int l = 0; l < 2; ++l) x[l] = position(g, l, k[l] + u(gen));
    BOOST_TEST_REQUIRE(g.locate(x, xi) == g.flatten(k));
    for (int l = 0; l < 2; ++l) {
      BOOST_TEST_REQUIRE((xi[l] > 0.0 && xi[l] < 1.0));
      BOOST_TEST_REQUIRE(std::abs(position(g, l, k[l] + xi[l]) - x[l]) <= 1e-14);
    }
  }
}

BOOST_AUTO_TEST_CASE(a_point_on_a_face_belongs_to_the_plus_cell_at_xi_zero) {
  for (const bool periodic : {false, true}) {
    const Grid<2> g = plate(periodic);
    for (int face = 0; face <= 13; ++face)
      for (const double off : {0.0, 3e-16, -3e-16, 4e-13, -4e-13}) {
        // Off the face by round-off (4e-13 of the cells counted, or of one, is under the snap).
        const Grid<2>::Vec x(position(g, 0, face + off * std::max(1, face)), position(g, 1, 2.5));
        Grid<2>::Vec xi = Grid<2>::Vec::Zero();
        const int c = g.locate(x, xi);
        if (face < 13) {
          BOOST_TEST_REQUIRE(c == g.flatten({face, 2}));
          BOOST_TEST_REQUIRE(xi[0] == 0.0);
        } else if (periodic) {  // the upper face is the first one
          BOOST_TEST_REQUIRE(c == g.flatten({0, 2}));
          BOOST_TEST_REQUIRE(xi[0] == 0.0);
        } else {  // the upper boundary: the last cell's
          BOOST_TEST_REQUIRE(c == g.flatten({12, 2}));
          BOOST_TEST_REQUIRE(xi[0] == 1.0);
        }
      }
  }
}

BOOST_AUTO_TEST_CASE(off_a_non_periodic_axis_or_not_finite_is_outside) {
  const Grid<2> g = plate(true);  // x periodic, y not
  Grid<2>::Vec xi = Grid<2>::Vec::Zero();
  for (const double y : {-1e-9, 7.0 + 1e-9, -5.0, 100.0})
    BOOST_TEST(g.locate(Grid<2>::Vec(position(g, 0, 3.5), position(g, 1, y)), xi) == -1);
  const double nan = std::numeric_limits<double>::quiet_NaN();
  const double inf = std::numeric_limits<double>::infinity();
  for (const double bad : {nan, inf, -inf}) {
    BOOST_TEST(g.locate(Grid<2>::Vec(bad, position(g, 1, 1.5)), xi) == -1);
    BOOST_TEST(g.locate(Grid<2>::Vec(position(g, 0, 1.5), bad), xi) == -1);
  }
  // Just inside the lower and upper faces of y: the first and last rows.
  BOOST_TEST(g.locate(Grid<2>::Vec(position(g, 0, 3.5), position(g, 1, 1e-6)), xi) ==
             g.flatten({3, 0}));
  BOOST_TEST(g.locate(Grid<2>::Vec(position(g, 0, 3.5), position(g, 1, 7 - 1e-6)), xi) ==
             g.flatten({3, 6}));
}

BOOST_AUTO_TEST_CASE(a_periodic_axis_wraps_whole_periods) {
  const Grid<2> g = plate(true);
  std::mt19937 gen(11);
  std::uniform_real_distribution<double> u(0.001, 0.999);
  for (int n = 0; n < 2000; ++n) {
    const int k = static_cast<int>(gen() % 13);
    const double cells = k + u(gen);
    for (int period = -3; period <= 3; ++period) {
      const Grid<2>::Vec x(position(g, 0, cells + 13 * period), position(g, 1, 0.5));
      Grid<2>::Vec xi = Grid<2>::Vec::Zero();
      BOOST_TEST_REQUIRE(g.locate(x, xi) == g.flatten({k, 0}));
      BOOST_TEST_REQUIRE(std::abs(k + xi[0] - cells) <= 1e-12);
    }
  }
  // Just below the lower face: the last cell, near its upper face.
  Grid<2>::Vec xi = Grid<2>::Vec::Zero();
  BOOST_TEST(g.locate(Grid<2>::Vec(position(g, 0, -1e-6), position(g, 1, 0.5)), xi) ==
             g.flatten({12, 0}));
  BOOST_TEST(std::abs(xi[0] - (1 - 1e-6)) <= 1e-12);
}

BOOST_AUTO_TEST_CASE(a_window_gives_the_full_grids_coordinates_to_the_bit) {
  for (const bool periodic : {false, true}) {
    const Grid<2> full = plate(periodic);
    Grid<2> window = full;
    window.cells = {5, 4};
    window.first = {periodic ? 10 : 4, 2};  // periodic: cells 10, 11, 12, 0, 1 along x
    window.full.cells = full.cells;
    window.full.periodic = full.periodic;
    std::mt19937 gen(3);
    std::uniform_real_distribution<double> ux(-0.2, 13.2), uy(0.0, 7.0);
    int inside = 0;
    for (int n = 0; n < 20000; ++n) {
      const Grid<2>::Vec x(position(full, 0, ux(gen)), position(full, 1, uy(gen)));
      Grid<2>::Vec xi_full = Grid<2>::Vec::Zero(), xi_window = xi_full;
      const int c = full.locate(x, xi_full);
      const int w = window.locate(x, xi_window);
      if (c < 0) {
        BOOST_TEST_REQUIRE(w == -1);
        continue;
      }
      const Grid<2>::Index k = full.unflatten(c);
      Grid<2>::Index local = {k[0] - window.first[0], k[1] - window.first[1]};
      if (periodic) local[0] = (local[0] + 13) % 13;
      const bool held = local[0] >= 0 && local[0] < 5 && local[1] >= 0 && local[1] < 4;
      BOOST_TEST_REQUIRE(w == (held ? window.flatten(local) : -1));
      if (!held) continue;
      ++inside;
      BOOST_TEST_REQUIRE(xi_window[0] == xi_full[0]);
      BOOST_TEST_REQUIRE(xi_window[1] == xi_full[1]);
    }
    BOOST_TEST(inside > 1000);
  }
}
