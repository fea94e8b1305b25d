#include "stability/one_step_map.hpp"

#include "stability/periodic_cells.hpp"

#include <Eigen/LU>
#include <cmath>
#include <sstream>
#include <stdexcept>

namespace dgmpm::stability {
namespace {

// Offsets -kWindow..kWindow are observed along each axis; a response at +-kWindow means the
// stencil may wrap around the periodic grid, so it is refused rather than aliased.
constexpr int kWindow = 4;
constexpr int kCells = 2 * kWindow + 1;
constexpr int kHome = kWindow;

// The observed offsets: index o <-> (d_x, d_y) = (o % kCells - kWindow, o / kCells - kWindow)
// (1D: kCells offsets, d_y = 0).
template <int Dim>
constexpr int kOffsets = Dim == 1 ? kCells : kCells* kCells;
std::pair<int, int> offset_of(int o, int dim) {
  return {o % kCells - kWindow, dim == 1 ? 0 : o / kCells - kWindow};
}

// blocks[o](c_out * N + i, c_in * N + j): response of component c_out of particle i in cell
// home + d(o) to a unit value of component c_in of particle j in cell home.
template <class Physics>
std::vector<Eigen::MatrixXd> sample_blocks(PeriodicCells<Physics>& grid, double courant) {
  constexpr int ncomp = Physics::n_comp, dim = Physics::dim;
  const int n = grid.particles_per_cell(), m = ncomp * n;
  const auto cell = [&grid](int dx, int dy) {
    typename Grid<dim>::Index k{};
    k[0] = kHome + dx;
    if constexpr (dim > 1) k[1] = kHome + dy;
    return grid.cell_index(k);
  };
  const int home = cell(0, 0);
  std::vector<Eigen::MatrixXd> blocks(kOffsets<dim>, Eigen::MatrixXd::Zero(m, m));
  for (int c_in = 0; c_in < ncomp; ++c_in)
    for (int j = 0; j < n; ++j) {
      grid.state().setZero();
      grid.state()(c_in, home * n + j) = 1.0;
      grid.step(courant);
      for (int o = 0; o < kOffsets<dim>; ++o) {
        const auto [dx, dy] = offset_of(o, dim);
        const int e = cell(dx, dy);
        for (int c_out = 0; c_out < ncomp; ++c_out)
          for (int i = 0; i < n; ++i)
            blocks[o](c_out * n + i, c_in * n + j) = grid.state()(c_out, e * n + i);
      }
    }
  return blocks;
}

double max_abs(const std::vector<Eigen::MatrixXd>& blocks) {
  double s = 0.0;
  for (const auto& b : blocks) s = std::max(s, b.cwiseAbs().maxCoeff());
  return s;
}

// coefficients[d + kWindow][k] of the full (ncomp N)-square blocks.
// `round_off` receives the round-off level of the samples: lib's nodal values divide by the nodal
// masses, so a node holding a small share of its cell's mass amplifies it (RK2 carries O(1 / share)
// stage values to the neighbours before interpolation brings them back to O(1)).
template <class Physics>
std::vector<std::vector<Eigen::MatrixXd>>
polynomial_blocks(const CellLayout& layout, const AnalysisSetting& setting, double& round_off) {
  const int degree = polynomial_degree(setting);
  PeriodicCells<Physics> grid(layout, kCells, setting);
  round_off = 1e-15 / grid.smallest_node_share();
  // Nodes j / degree in [0, 1]: exact in binary, and a well-conditioned Vandermonde system.
  Eigen::MatrixXd vandermonde(degree + 1, degree + 1);
  std::vector<std::vector<Eigen::MatrixXd>> samples;
  for (int j = 0; j <= degree; ++j) {
    const double c = static_cast<double>(j) / degree;
    for (int k = 0; k <= degree; ++k) vandermonde(j, k) = std::pow(c, k);
    samples.push_back(sample_blocks(grid, c));
  }
  const Eigen::MatrixXd inverse = vandermonde.fullPivLu().inverse();
  const int offsets = kOffsets<Physics::dim>;
  std::vector<std::vector<Eigen::MatrixXd>> coefficients(offsets);
  for (int d = 0; d < offsets; ++d)
    for (int k = 0; k <= degree; ++k) {
      Eigen::MatrixXd sum = Eigen::MatrixXd::Zero(samples[0][d].rows(), samples[0][d].cols());
      for (int j = 0; j <= degree; ++j) sum += inverse(k, j) * samples[j][d];
      coefficients[d].push_back(sum);
    }

  // One more application checks that lib's step really is this polynomial in dt.
  const double check_courant = 0.75;
  const auto check = sample_blocks(grid, check_courant);
  double error = 0.0;
  for (int d = 0; d < offsets; ++d) {
    Eigen::MatrixXd value = coefficients[d][degree];
    for (int k = degree - 1; k >= 0; --k) value = value * check_courant + coefficients[d][k];
    error = std::max(error, (value - check[d]).cwiseAbs().maxCoeff());
  }
  const double tolerance = std::max(1e-12, 10.0 * round_off);
  if (error > tolerance * std::max(1.0, max_abs(check))) {
    std::ostringstream s;
    s << "the one-step map of lib's " << to_string(setting.time) << " integrator ("
      << to_string(setting.flux) << ") is not a polynomial of degree " << degree
      << " in dt (mismatch " << error << ")";
    throw std::logic_error(s.str());
  }
  return coefficients;
}

// Family of the unknowns [first, first + size) of the (transformed) blocks.
StencilFamily extract_family(const std::vector<std::vector<Eigen::MatrixXd>>& coefficients,
                             int first, int size, int n, const std::string& direction,
                             double round_off) {
  double scale = 0.0;
  for (const auto& by_power : coefficients) scale = std::max(scale, max_abs(by_power));
  const double negligible = std::max(1e-14 * scale, 10.0 * round_off);
  StencilFamily f;
  f.direction = direction;
  f.size = size;
  for (int r = 0; r < size; ++r) f.particle.push_back((first + r) % n);
  for (std::size_t o = 0; o < coefficients.size(); ++o) {
    std::vector<Eigen::MatrixXd> part;
    double largest = 0.0;
    for (const auto& c : coefficients[o]) {
      part.push_back(c.block(first, first, size, size));
      largest = std::max(largest, part.back().cwiseAbs().maxCoeff());
    }
    if (largest <= negligible) continue;
    const int dim = coefficients.size() == kOffsets<1> ? 1 : 2;
    const auto [dx, dy] = offset_of(static_cast<int>(o), dim);
    if (std::abs(dx) == kWindow || std::abs(dy) == kWindow)
      throw std::logic_error("the one-step map reaches further than the analysis window (+-" +
                             std::to_string(kWindow - 1) + " cells)");
    f.offsets.push_back(dx);
    f.offsets_y.push_back(dy);
    f.coefficients.push_back(std::move(part));
  }
  return f;
}

}  // namespace

Eigen::MatrixXd StencilFamily::block(std::size_t offset_index, double courant) const {
  const auto& c = coefficients[offset_index];
  Eigen::MatrixXd value = c.back();
  for (int k = static_cast<int>(c.size()) - 2; k >= 0; --k) value = value * courant + c[k];
  return value;
}

OneStepMap build_one_step_map(const CellLayout& layout, TimeScheme scheme, Model model) {
  AnalysisSetting setting;
  setting.time = scheme;
  setting.model = model;
  return build_one_step_map(layout, setting);
}

OneStepMap build_one_step_map(const CellLayout& layout, const AnalysisSetting& setting) {
  validate(layout);
  if (layout.dim != setting.dim)
    throw std::invalid_argument("a " + std::to_string(layout.dim) + "D layout for a " +
                                std::to_string(setting.dim) + "D analysis");
  OneStepMap map{layout, setting, polynomial_degree(setting), {}};
  const int n = layout.size();
  const Model model = setting.model;
  if (setting.dim == 2) {
    if (model == Model::advection) {
      const auto coefficients = polynomial_blocks<Advection<2>>(layout, setting, map.round_off);
      map.families.push_back(extract_family(coefficients, 0, n, n, "+x+y", map.round_off));
    } else {
      const auto coefficients = polynomial_blocks<PlaneStrain>(layout, setting, map.round_off);
      map.families.push_back(
          extract_family(coefficients, 0, PlaneStrain::n_comp * n, n, "all", map.round_off));
    }
    return map;
  }
  if (model == Model::advection) {
    const auto coefficients = polynomial_blocks<Advection<1>>(layout, setting, map.round_off);
    map.families.push_back(extract_family(coefficients, 0, n, n, "+x", map.round_off));
    return map;
  }
  // Specific state (sigma / rho, v); w+ = sigma/rho - c v travels to +x, w- = sigma/rho + c v
  // to -x. In these variables the blocks become T B T^-1.
  auto coefficients = polynomial_blocks<ElasticBar>(layout, setting, map.round_off);
  const double c = unit_material<ElasticBar>().wave_speed();
  Eigen::MatrixXd t(2 * n, 2 * n), t_inverse(2 * n, 2 * n);
  const Eigen::MatrixXd id = Eigen::MatrixXd::Identity(n, n);
  t << id, -c * id, id, c * id;
  t_inverse << 0.5 * id, 0.5 * id, -0.5 / c * id, 0.5 / c * id;
  double scale = 0.0, coupling = 0.0;
  for (auto& by_power : coefficients)
    for (auto& b : by_power) {
      b = t * b * t_inverse;
      scale = std::max(scale, b.cwiseAbs().maxCoeff());
      coupling = std::max({coupling, b.topRightCorner(n, n).cwiseAbs().maxCoeff(),
                           b.bottomLeftCorner(n, n).cwiseAbs().maxCoeff()});
    }
  const double e = map.round_off;
  if (coupling <= std::max(1e-12 * scale, 10.0 * e)) {
    map.families.push_back(extract_family(coefficients, 0, n, n, "+x", e));
    map.families.push_back(extract_family(coefficients, n, n, n, "-x", e));
  } else {
    map.families.push_back(extract_family(coefficients, 0, 2 * n, n, "both", e));
  }
  return map;
}

double OneStepMap::round_off_level() const {
  // A row or an eigenvalue sums at most (unknowns x offsets) entries, each off by round_off.
  std::size_t terms = 0;
  for (const auto& f : families) terms = std::max(terms, f.size * f.offsets.size());
  return round_off * static_cast<double>(terms);
}

Eigen::MatrixXcd amplification_matrix(const StencilFamily& family, double courant, double theta,
                                      double theta_y) {
  Eigen::MatrixXcd g = Eigen::MatrixXcd::Zero(family.size, family.size);
  for (std::size_t i = 0; i < family.offsets.size(); ++i)
    g += std::polar(1.0, -family.offsets[i] * theta - family.offsets_y[i] * theta_y) *
         family.block(i, courant).cast<std::complex<double>>();
  return g;
}

}  // namespace dgmpm::stability
