// Block decomposition of a grid over a Cartesian array of ranks: the blocks tile the grid (each
// cell owned once, by the rank owner() names), are balanced to one layer, ranks are numbered as
// MPI_Cart_rank numbers them, neighbours are symmetric and wrap on periodic axes only, and the
// ghost layer of a rank's window is exactly the cells outside its block that its cells' 3^d
// stencils reach, and a window (a block and its ghost layers) locates points as the full grid does.
// A rank's subdomain: its window's cells map back to the grid's, its exchange partners are the
// owners of its ghost cells (and list it in turn), its boundaries are the grid's on the grid's
// sides only. A point with a nonfinite coordinate is off the grid, periodic axes included.
#define BOOST_TEST_MODULE lib_decomposition
#include <boost/test/unit_test.hpp>

#include "common/grids.hpp"

#include <dgmpm/decomposition.hpp>
#include <dgmpm/subdomain.hpp>

#include <algorithm>
#include <limits>
#include <optional>
#include <random>
#include <set>
#include <stdexcept>
#include <vector>

using namespace dgmpm;
using test::grid;

namespace {

// Every offset in {-1, 0, 1}^D but zero.
template <int D>
std::vector<std::array<int, D>> stencil() {
  std::vector<std::array<int, D>> out;
  int n = 1;
  for (int l = 0; l < D; ++l) n *= 3;
  for (int m = 0; m < n; ++m) {
    std::array<int, D> o{};
    bool zero = true;
    for (int l = 0, r = m; l < D; ++l, r /= 3) {
      o[l] = r % 3 - 1;
      zero = zero && o[l] == 0;
    }
    if (!zero) out.push_back(o);
  }
  return out;
}

template <int D>
void check(const Grid<D>& g, const std::array<int, D>& layout) {
  const BlockDecomposition<D> b(g, layout);
  const int nr = b.num_ranks();
  // Rank numbers: the first axis varies slowest (MPI_Cart_rank's row-major order).
  for (int r = 0; r < nr; ++r) {
    const auto k = b.coords(r);
    int expected = 0;
    for (int l = 0; l < D; ++l) expected = expected * layout[l] + k[l];
    BOOST_TEST(expected == r);
    BOOST_TEST(b.rank(k) == r);
  }
  // Balance: along each axis the blocks' sizes differ by one at most, none empty.
  for (int l = 0; l < D; ++l) {
    int smallest = g.cells[l], largest = 0;
    for (int k = 0; k < layout[l]; ++k) {
      const int size = b.first_cell(l, k + 1) - b.first_cell(l, k);
      smallest = std::min(smallest, size);
      largest = std::max(largest, size);
    }
    BOOST_TEST(smallest >= 1);
    BOOST_TEST(largest - smallest <= 1);
    BOOST_TEST(b.first_cell(l, layout[l]) == g.cells[l]);
  }
  // Tiling: each cell in exactly one box, that of owner(); the owned counts add up.
  std::vector<int> owners(g.num_cells(), 0);
  long owned = 0;
  for (int r = 0; r < nr; ++r) {
    owned += b.owned_cells(r);
    const auto lo = b.lower(r), hi = b.upper(r);
    for (int c = 0; c < g.num_cells(); ++c) {
      const auto k = g.unflatten(c);
      bool inside = true;
      for (int l = 0; l < D; ++l) inside = inside && k[l] >= lo[l] && k[l] < hi[l];
      if (!inside) continue;
      ++owners[c];
      BOOST_TEST(b.owner(k) == r);
    }
  }
  BOOST_TEST(owned == g.num_cells());
  for (int c = 0; c < g.num_cells(); ++c) BOOST_TEST(owners[c] == 1);
  // Neighbours: symmetric; -1 exactly past a non-periodic side.
  for (int r = 0; r < nr; ++r)
    for (const auto& o : stencil<D>()) {
      const int n = b.neighbour(r, o);
      auto back = o;
      for (auto& x : back) x = -x;
      const auto k = b.coords(r);
      bool past = false;
      for (int l = 0; l < D; ++l)
        past = past || (!g.periodic[l] && (k[l] + o[l] < 0 || k[l] + o[l] >= layout[l]));
      BOOST_TEST((n < 0) == past);
      if (n >= 0) BOOST_TEST(b.neighbour(n, back) == r);
    }
  // Ghost layer: a rank's window of depth 1 holds, beyond its block, the cells other ranks own
  // that the owned cells' stencils reach (the grid's own wrap rules), nothing more.
  for (int r = 0; r < nr; ++r) {
    const Grid<D> window = b.window(g, r, 1);
    std::set<int> reached;
    for (int c = 0; c < g.num_cells(); ++c) {
      if (b.owner(g.unflatten(c)) != r) continue;
      for (const auto& o : stencil<D>()) {
        int n = c;
        for (int l = 0; l < D && n >= 0; ++l)
          if (o[l] != 0) n = g.neighbour(n, l, o[l] > 0);
        if (n >= 0 && b.owner(g.unflatten(n)) != r) reached.insert(n);
      }
    }
    for (int c = 0; c < g.num_cells(); ++c) {
      const auto k = g.unflatten(c);
      typename Grid<D>::Vec centre, xi;
      for (int l = 0; l < D; ++l) centre[l] = g.origin[l] + (k[l] + 0.5) * g.cell_size[l];
      const bool ghost = window.locate(centre, xi) >= 0 && b.owner(k) != r;
      BOOST_TEST(ghost == (reached.count(c) == 1), "rank " << r << " cell " << c);
    }
  }
  // Windows: a block and `depth` layers around it, locating points as the full grid does (the
  // same local coordinates, to the bit), holding exactly the cells within `depth` of the block.
  Grid<D> full = g;
  full.origin.setConstant(-0.3);
  full.cell_size.setConstant(0.7);
  std::mt19937 rng(7);
  std::uniform_real_distribution<double> fraction(0.0, 1.0);
  for (int depth : {1, 2})
    for (int r = 0; r < nr; ++r) {
      const auto lo = b.lower(r), hi = b.upper(r);
      bool too_deep = false;
      for (int l = 0; l < D; ++l)
        too_deep =
            too_deep || (g.periodic[l] && layout[l] > 1 && hi[l] - lo[l] + 2 * depth > g.cells[l]);
      if (too_deep) {
        BOOST_CHECK_THROW(b.window(full, r, depth), std::invalid_argument);
        continue;
      }
      const Grid<D> w = b.window(full, r, depth);
      // A subdomain needs every rank's window (its partners'): refused with any.
      bool all_fit = true;
      for (int q = 0; q < nr; ++q)
        for (int l = 0; l < D; ++l)
          all_fit = all_fit && !(g.periodic[l] && layout[l] > 1 &&
                                 b.upper(q)[l] - b.lower(q)[l] + 2 * depth > g.cells[l]);
      std::optional<Subdomain<D>> sub;
      if (all_fit)
        sub.emplace(full, b, r, depth);
      else
        BOOST_CHECK_THROW(Subdomain<D>(full, b, r, depth), std::invalid_argument);
      std::set<int> owners;  // of the window's cells but r: the partners
      int held = 0;
      for (int c = 0; c < g.num_cells(); ++c) {
        const auto k = g.unflatten(c);
        typename Grid<D>::Vec x, xi_full = Grid<D>::Vec::Zero(), xi_window = xi_full;
        for (int l = 0; l < D; ++l)
          x[l] = full.origin[l] + (k[l] + fraction(rng)) * full.cell_size[l];
        BOOST_TEST_REQUIRE(full.locate(x, xi_full) == c);
        const int cw = w.locate(x, xi_window);
        bool near = true;  // within depth of the block along every axis
        for (int l = 0; l < D; ++l) {
          const int n = g.cells[l];
          int below = lo[l] - k[l], above = k[l] - (hi[l] - 1);
          if (g.periodic[l]) {
            below = (below % n + n) % n;
            above = (above % n + n) % n;
          }
          const bool in_block = k[l] >= lo[l] && k[l] < hi[l];
          near = near && (in_block || w.periodic[l] || (below > 0 && below <= depth) ||
                          (above > 0 && above <= depth));
        }
        BOOST_TEST((cw >= 0) == near, "rank " << r << " depth " << depth << " cell " << c);
        if (cw < 0) continue;
        ++held;
        if (sub) BOOST_TEST(full.flatten(sub->full_cell(cw)) == c);
        if (b.owner(k) != r) owners.insert(b.owner(k));
        BOOST_TEST(((xi_window.array() == xi_full.array()).all()));
        const auto kw = w.unflatten(cw);
        for (int l = 0; l < D; ++l)
          BOOST_TEST(((w.first[l] + kw[l]) % g.cells[l] + g.cells[l]) % g.cells[l] == k[l]);
      }
      BOOST_TEST(held == w.num_cells());  // each window cell is a distinct cell of the grid
      if (!sub) continue;
      BOOST_TEST(sub->window().num_cells() == w.num_cells());
      const std::vector<int> partners(owners.begin(), owners.end());
      BOOST_TEST(sub->partners() == partners, "rank " << r << " depth " << depth);
      for (int q : sub->partners()) {  // symmetric: the exchanges pair up
        const Subdomain<D> other(full, b, q, depth);
        const auto& back = other.partners();
        BOOST_TEST((std::find(back.begin(), back.end(), r) != back.end()));
      }
      // The grid's conditions on the grid's sides only: free inside, none on periodic axes.
      Boundaries<D> everywhere;
      for (auto& axis : everywhere)
        for (auto& side : axis) side = BoundaryCondition<D>{BoundaryKind::fixed, {}};
      const Boundaries<D> kept = sub->boundaries(everywhere);
      for (int l = 0; l < D; ++l) {
        const bool lower = !g.periodic[l] && lo[l] - depth <= 0;
        const bool upper = !g.periodic[l] && hi[l] + depth >= g.cells[l];
        BOOST_TEST(kept[l][0].segments.size() == (lower ? 1u : 0u), "rank " << r << " axis " << l);
        BOOST_TEST(kept[l][1].segments.size() == (upper ? 1u : 0u), "rank " << r << " axis " << l);
      }
    }
}

}  // namespace

BOOST_AUTO_TEST_CASE(one_dimension) {
  for (bool periodic : {false, true})
    for (int ranks : {1, 2, 3, 7}) check<1>(grid<1>({7}, {periodic}), {ranks});
}

BOOST_AUTO_TEST_CASE(two_dimensions) {
  for (bool px : {false, true})
    for (bool py : {false, true})
      for (const std::array<int, 2>& layout : {std::array{1, 1}, std::array{2, 3}, std::array{3, 1},
                                               std::array{4, 2}, std::array{10, 7}})
        check<2>(grid<2>({10, 7}, {px, py}), layout);
}

BOOST_AUTO_TEST_CASE(three_dimensions) {
  check<3>(grid<3>({5, 4, 6}, {false, true, false}), {2, 2, 3});
  check<3>(grid<3>({5, 4, 6}, {true, true, true}), {1, 2, 2});
}

// A point with a nonfinite coordinate (a particle moved by a blown-up velocity) is off the grid,
// along a periodic axis too.
BOOST_AUTO_TEST_CASE(nonfinite_points_are_off_the_grid) {
  for (bool periodic : {false, true}) {
    const Grid<2> g = grid<2>({10, 7}, {periodic, periodic});
    for (double bad :
         {std::numeric_limits<double>::quiet_NaN(), std::numeric_limits<double>::infinity(),
          -std::numeric_limits<double>::infinity()})
      for (int l = 0; l < 2; ++l) {
        Grid<2>::Vec x(2.5, 3.5), xi;
        BOOST_TEST_REQUIRE(g.locate(x, xi) == 32);
        x[l] = bad;
        BOOST_TEST(g.locate(x, xi) == -1, "periodic " << periodic << ", axis " << l << ": " << bad);
      }
  }
}

BOOST_AUTO_TEST_CASE(more_ranks_than_cells_is_refused) {
  BOOST_CHECK_THROW(BlockDecomposition<2>(grid<2>({10, 7}, {false, false}), {2, 8}),
                    std::invalid_argument);
  BOOST_CHECK_THROW(BlockDecomposition<1>(grid<1>({7}, {false}), {0}), std::invalid_argument);
}

// The rank layout: MPI's balanced one where it leaves every split axis kMinBlock cells per rank;
// otherwise the fitting layout with the fewest cut faces (a thin periodic strip goes along its
// length); MPI's when nothing fits (the decomposition then refuses it with its reason).
BOOST_AUTO_TEST_CASE(thin_grids_are_split_along_their_length) {
  using L = std::array<int, 2>;
  // The plate, 4 ranks: MPI's 2 x 2 fits and is kept.
  BOOST_TEST((rank_layout<2>(4, {33, 25}, {false, false}, {2, 2}) == L{2, 2}));
  // A strip of 200 x 2 cells periodic along y: 2 x 2 would leave one cell per rank along y.
  BOOST_TEST((rank_layout<2>(4, {200, 2}, {false, true}, {2, 2}) == L{4, 1}));
  BOOST_TEST((rank_layout<2>(6, {3, 300}, {false, false}, {3, 2}) == L{1, 6}));
  // MPI's layout is kept where it fits, even when another cuts fewer faces (runs keep their
  // layouts); where it does not, the fewest cut faces: 7 cuts of 7 faces.
  BOOST_TEST((rank_layout<2>(4, {40, 12}, {false, false}, {2, 2}) == L{2, 2}));
  BOOST_TEST((rank_layout<2>(8, {400, 7}, {false, false}, {4, 2}) == L{8, 1}));
  // Nothing fits: MPI's, refused later with the reason.
  BOOST_TEST((rank_layout<2>(4, {3, 3}, {false, false}, {2, 2}) == L{2, 2}));
  BOOST_TEST((rank_layout<1>(2, {50}, {false}, {2}) == std::array<int, 1>{2}));
}
