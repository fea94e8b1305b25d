#include "solver/scene.hpp"

#include <dgmpm/physics/finite_strain_bar.hpp>
#include <dgmpm/physics/finite_strain_plane.hpp>
#include <dgmpm/physics/small_strain.hpp>

#include <nlohmann/json.hpp>

#include <algorithm>
#include <cerrno>
#include <cfloat>
#include <climits>
#include <cmath>
#include <cstdio>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <initializer_list>
#include <iterator>
#include <limits>
#include <optional>
#include <set>
#include <sstream>
#include <utility>

namespace dgmpm::scene {

const char* to_string(Method m) {
  switch (m) {
    case Method::dgmpm:
      return "dgmpm";
    case Method::mpm_usl:
      return "mpm-usl";
    case Method::mpm_usf:
      return "mpm-usf";
    case Method::mpm_musl:
      return "mpm-musl";
  }
  return "?";
}

const char* to_string(MpmUpdate u) {
  switch (u) {
    case MpmUpdate::flip:
      return "flip";
    case MpmUpdate::pic:
      return "pic";
  }
  return "?";
}

// The models' names, in the order of MaterialModel's alternatives.
constexpr std::array<const char*, std::variant_size_v<MaterialModel>> model_names{
    "linear_elastic", "elastoplastic", "elasto_viscoplastic", "saint_venant_kirchhoff",
    "neo_hookean"};

const char* MaterialSpec::model_name() const {
  return model_names[model.index()];
}

namespace {

using json = nlohmann::json;

constexpr int max_particles_per_cell = 64;
constexpr std::size_t max_shown = 120;  // messages stay one readable line
const char* const axis_names[3] = {"x", "y", "z"};
const char* const side_keys[6] = {"xmin", "xmax", "ymin", "ymax", "zmin", "zmax"};

// As JSON writes it (shortest round trip), without a trailing ".0": 6 not 6.0.
std::string format_number(double v) {
  if (std::isnan(v)) return "nan";
  if (std::isinf(v)) return v > 0 ? "inf" : "-inf";
  std::string text = json(v).dump();
  if (text.size() > 2 && text.compare(text.size() - 2, 2, ".0") == 0) text.resize(text.size() - 2);
  return text;
}

// JSON cannot hold NaN or infinities (dump() prints null), but a document built in code can.
void show_into(const json& v, std::string& out) {
  if (out.size() > max_shown) return;
  if (v.is_number_float() && !std::isfinite(v.get<double>())) {
    out += format_number(v.get<double>());
  } else if (v.is_array()) {
    out += '[';
    for (std::size_t i = 0; i < v.size() && out.size() <= max_shown; ++i) {
      if (i > 0) out += ',';
      show_into(v[i], out);
    }
    out += ']';
  } else if (v.is_object()) {
    out += '{';
    for (auto it = v.begin(); it != v.end() && out.size() <= max_shown; ++it) {
      if (it != v.begin()) out += ',';
      out += json(it.key()).dump(-1, ' ', false, json::error_handler_t::replace);
      out += ':';
      show_into(it.value(), out);
    }
    out += '}';
  } else {
    out += v.dump(-1, ' ', false, json::error_handler_t::replace);
  }
}

// The value found, as JSON.
std::string show(const json& v) {
  std::string out;
  show_into(v, out);
  if (out.size() > max_shown) out = out.substr(0, max_shown - 3) + "...";
  return out;
}

std::string join(const std::vector<std::string>& names) {
  std::string out;
  for (const auto& n : names) out += (out.empty() ? "" : ", ") + n;
  return out;
}

std::string key_path(const std::string& parent, const std::string& key) {
  // Control characters (a NUL would cut the message short) are shown as JSON escapes.
  std::string shown;
  for (const char ch : key) {
    if (static_cast<unsigned char>(ch) < 0x20 || ch == 0x7f) {
      char escape[8];
      std::snprintf(escape, sizeof escape, "\\u%04x", static_cast<unsigned char>(ch));
      shown += escape;
    } else {
      shown += ch;
    }
  }
  return parent.empty() ? shown : parent + "." + shown;
}

std::string index_path(const std::string& parent, std::size_t i) {
  return parent + "[" + std::to_string(i) + "]";
}

std::string numbers_text(const std::vector<double>& v) {
  std::string out = "[";
  for (std::size_t i = 0; i < v.size(); ++i) out += (i ? ", " : "") + format_number(v[i]);
  return out + "]";
}

std::size_t stress_size(int dimension) {
  return static_cast<std::size_t>(dimension * (dimension + 1) / 2);
}

// Range of cells along `axis` that can hold a point of [lo, hi) (one cell of margin against
// rounding), clamped to the grid.
std::pair<int, int> cell_range(const GridSpec& grid, double lo, double hi, int axis) {
  const auto a = static_cast<std::size_t>(axis);
  const double origin = grid.origin[a], h = grid.cell_size[a];
  const double last_cell = grid.cells[a] - 1.0;
  const double first = std::clamp(std::floor((lo - origin) / h) - 1, 0.0, last_cell);
  const double last = std::clamp(std::ceil((hi - origin) / h) + 1, 0.0, last_cell);
  return {static_cast<int>(first), static_cast<int>(last)};
}

// Calls f(seed) for the points of `body`'s layout in the cells whose ranges along each axis are
// `ranges`, claimed by the box [box_min, box_max); stops early when f returns false.
template <class F>
void for_each_seed(const Scene& scene, const BodySpec& body,
                   const std::array<std::pair<int, int>, 3>& ranges, F&& f) {
  const int dim = scene.dimension;
  std::array<int, 3> k{};
  for (int a = 0; a < dim; ++a) {
    k[static_cast<std::size_t>(a)] = ranges[static_cast<std::size_t>(a)].first;
    if (ranges[static_cast<std::size_t>(a)].first > ranges[static_cast<std::size_t>(a)].second)
      return;
  }
  while (true) {
    for (std::size_t j = 0; j < body.layout.size(); ++j) {
      Seed seed;
      bool inside = true;
      for (std::size_t a = 0; a < static_cast<std::size_t>(dim); ++a) {
        const double x = scene.grid.origin[a] +
                         (static_cast<double>(k[a]) + body.layout[j][a]) * scene.grid.cell_size[a];
        seed.cell[a] = k[a];
        seed.x[a] = x;
        if (!(body.box_min[a] <= x && x < body.box_max[a])) inside = false;
      }
      seed.local = static_cast<int>(j);
      if (inside && !f(seed)) return;
    }
    int a = 0;
    for (; a < dim; ++a) {
      const auto ax = static_cast<std::size_t>(a);
      if (++k[ax] <= ranges[ax].second) break;
      k[ax] = ranges[ax].first;
    }
    if (a == dim) return;
  }
}

template <class E>
using Names = std::initializer_list<std::pair<const char*, E>>;

class Parser {
 public:
  explicit Parser(std::string source) : source_(std::move(source)) {}

  Scene parse(const json& doc) {
    Scene s;
    s.source = source_;
    check_object(doc, "",
                 {"dimension", "method", "update", "grid", "materials", "bodies", "boundaries",
                  "time", "particles_move", "fill_correction", "formulation", "flux", "plane_wave",
                  "exact", "output", "strain"});
    s.dimension = parse_dimension(require(doc, "", "dimension", "1"));
    if (const json* m = find(doc, "method"))
      s.method =
          named(*m, "method", {Method::dgmpm, Method::mpm_usl, Method::mpm_usf, Method::mpm_musl});
    if (const json* u = find(doc, "update")) {
      if (s.method == Method::dgmpm)
        refuse("update", *u, "is not allowed with method \"dgmpm\"",
               "update only with mpm-usl, mpm-usf or mpm-musl");
      s.update = named(*u, "update", {MpmUpdate::flip, MpmUpdate::pic});
    }
    s.grid = parse_grid(require(doc, "", "grid", "an object with origin, cell_size, cells"),
                        s.dimension);
    s.materials = parse_materials(
        require(doc, "", "materials", "an object of materials, e.g. {\"steel\": {...}}"));
    s.time = parse_time(require(doc, "", "time", "an object with at least \"end\""));
    s.bodies = parse_bodies(require(doc, "", "bodies", "an array of bodies"), s);
    check_seeds(s, doc["bodies"]);
    if (const json* b = find(doc, "boundaries")) parse_boundaries(*b, s);
    if (const json* p = find(doc, "particles_move"))
      s.particles_move = boolean(*p, "particles_move");
    if (const json* k = find(doc, "strain")) {
      const std::string allowed =
          "\"uniaxial_stress\" (a bar, the default) or \"uniaxial_strain\" (a plane wave), 1D "
          "only";
      if (s.dimension != 1) refuse("strain", *k, "is a 1D option", allowed);
      s.uniaxial_strain =
          choice<int>(*k, "strain", {{"uniaxial_stress", 0}, {"uniaxial_strain", 1}}) == 1;
    }
    if (const json* f = find(doc, "fill_correction"))
      refuse("fill_correction", *f,
             "is no longer read: \"formulation\": \"consistent\" (the default) preserves "
             "constant states in every cell, part-full and over-full ones included",
             "no fill_correction key (\"formulation\": \"paper\" for the paper's form)");
    if (const json* k = find(doc, "formulation")) {
      if (s.method != Method::dgmpm)
        refuse("formulation", *k, "is a DGMPM option", "formulation only with \"dgmpm\"");
      s.formulation = named(*k, "formulation", {Formulation::consistent, Formulation::paper});
    }
    if (const json* f = find(doc, "flux")) {
      if (s.dimension == 1 || s.method != Method::dgmpm)
        refuse("flux", *f,
               "is not allowed with " + std::to_string(s.dimension) + "D method \"" +
                   to_string(s.method) + "\"",
               "flux only with 2D method \"dgmpm\" (1D has one flux)");
      s.flux = named(*f, "flux", {FluxScheme::dcu, FluxScheme::ctu});
    }
    if (const json* w = find(doc, "plane_wave")) s.plane_wave = parse_plane_wave(*w, s);
    if (const json* e = find(doc, "exact")) {
      if (s.dimension == 1) {
        choice<int>(*e, "exact", {{"bar", 0}});
        s.exact = "bar";
      } else {
        choice<int>(*e, "exact", {{"plane_wave", 0}});
        if (!s.plane_wave)
          refuse("exact", *e, "needs a \"plane_wave\" key", "\"plane_wave\" with a plane_wave");
        s.exact = "plane_wave";
      }
    }
    s.output.times = {s.time.end};
    s.output.vtu = s.output.vtu_binary = s.dimension > 1;
    if (const json* o = find(doc, "output")) parse_output(*o, s);
    check_double_range(s, doc);
    check_finite_strain(s, doc);
    return s;
  }

 private:
  std::string source_;

  // Values each valid alone can ask for physics outside the range of a double (a modulus of
  // 1e308, a velocity of 1e308 m/s, a cell of 1e-320 m): the wave speed, impedance, the stress an
  // impact makes, its energy density and the time step must be finite, normal numbers, or the
  // first step turns them into inf or nan. Refused before any step, with the key responsible.
  void check_double_range(const Scene& s, const json& doc) const {
    const auto normal = [](double x) { return std::isfinite(x) && std::abs(x) >= DBL_MIN; };
    const bool plane = s.dimension > 1;
    std::vector<double> modulus, speed, impedance;
    for (const MaterialSpec& m : s.materials) {
      const double nu = m.poisson;
      const double mod = plane ? m.young * (1 - nu) / ((1 + nu) * (1 - 2 * nu)) : m.young;
      const double c = std::sqrt(mod / m.density), z = std::sqrt(mod * m.density);
      if (!(normal(mod) && normal(mod / m.density) && normal(mod * m.density) && normal(c * z)))
        refuse(key_path("materials", m.name), doc["materials"][m.name],
               "asks for a wave speed or impedance outside the range of a double (c = " +
                   number_text(c) + " m/s, Z = " + number_text(z) + " kg/m^2/s)",
               "a modulus and density whose ratio and product are normal doubles");
      modulus.push_back(mod), speed.push_back(c), impedance.push_back(z);
    }
    for (std::size_t i = 0; i < s.bodies.size(); ++i) {
      const BodySpec& b = s.bodies[i];
      const int k = b.material;
      double v = 0, sigma = 0;
      for (double x : b.velocity) v = std::max(v, std::abs(x));
      for (double x : b.stress) sigma = std::max(sigma, std::abs(x));
      // The stress an impact at v makes is Z v; the energy density sigma^2 / M + rho v^2.
      const double stress = std::max(sigma, impedance[k] * v);
      const double energy = stress / modulus[k] * stress + impedance[k] / speed[k] * v * v;
      if (!(std::isfinite(stress) && std::isfinite(energy) && std::isfinite(stress * speed[k]))) {
        const bool by_velocity = impedance[k] * v >= sigma;
        const std::string key = by_velocity ? "velocity" : "stress";
        const std::string path = key_path(index_path("bodies", i), key);
        refuse(path, doc["bodies"][i][key],
               "makes stresses or energies outside the range of a double with material \"" +
                   s.materials[k].name + "\"",
               "values whose stress (and impedance times velocity) squared over the modulus is a "
               "finite double");
      }
    }
    double h = std::numeric_limits<double>::infinity(), c_max = 0;
    for (std::size_t a = 0; a < s.grid.cell_size.size(); ++a) {
      h = std::min(h, s.grid.cell_size[a]);
      if (!std::isfinite(s.grid.upper(a)))
        refuse(index_path("grid.cells", a), doc["grid"]["cells"][a],
               "makes the grid's extent overflow a double", "origin + cells * cell_size finite");
    }
    for (double c : speed) c_max = std::max(c_max, c);
    const double dt = (s.time.courant_auto ? 1.0 : s.time.courant) * h / c_max;
    if (!normal(h) || !normal(dt))
      refuse("grid.cell_size", doc["grid"]["cell_size"],
             "gives a time step of " + number_text(dt) + " s, not a normal double",
             "cell sizes whose time step c dt / h = C is a normal double (above 2.2e-308 s)");
  }

  // Finite-strain materials: one hyperelastic law for the whole scene, bodies given a deformation
  // gradient rather than a stress, states inside the law's hyperbolic range.
  void check_finite_strain(Scene& s, const json& doc) const {
    const MaterialSpec* finite = nullptr;
    const MaterialSpec* small = nullptr;
    for (const MaterialSpec& m : s.materials) (m.finite_strain() ? finite : small) = &m;
    if (!finite) {
      for (std::size_t i = 0; i < s.bodies.size(); ++i)
        if (!s.bodies[i].deformation_gradient.empty())
          refuse(key_path(index_path("bodies", i), "deformation_gradient"),
                 doc["bodies"][i]["deformation_gradient"],
                 "is a finite-strain key and material \"" + s.materials[s.bodies[i].material].name +
                     "\" is small-strain",
                 "deformation_gradient with \"saint_venant_kirchhoff\" or \"neo_hookean\"");
      return;
    }
    const json& model = doc["materials"][finite->name]["model"];
    if (small)
      refuse(model_path(*finite), model,
             "mixes finite strain with the small-strain material \"" + small->name +
                 "\" (model \"" + small->model_name() +
                 "\"): the two measure strain and stress differently, and no edge state joins them",
             "every material of a scene finite-strain, or none");
    for (const MaterialSpec& m : s.materials)
      if (m.model.index() != finite->model.index())
        refuse(model_path(m), doc["materials"][m.name]["model"],
               "is a second hyperelastic law beside \"" + std::string(finite->model_name()) +
                   "\" of material \"" + finite->name + "\"",
               "one law per scene (materials may differ in young, poisson and density)");
    const std::string fs = "with finite-strain material \"" + finite->name + "\"";
    if (s.particles_move)
      refuse("particles_move", doc["particles_move"],
             "is not allowed " + fs +
                 ": the formulation is total Lagrangian (DGMPM and the MPM baseline alike): "
                 "particles stay at their reference positions and carry their displacement "
                 "(outputs give the current positions)",
             "false");
    if (const json* k = find(doc, "strain"); k && !s.uniaxial_strain)
      refuse("strain", *k, "is not allowed " + fs + ": 1D finite strain is uniaxial strain",
             "\"uniaxial_strain\" or no strain key");
    if (s.exact)
      refuse("exact", doc["exact"], "is not available " + fs + " (the exact bar is small-strain)",
             "no exact key (the finite-strain tests compute their exact solutions)");
    if (s.time.check_scene_every > 0)
      refuse("time.check_scene_every", doc["time"]["check_scene_every"],
             "is not available " + fs +
                 ": the check evaluates the whole scene's step as a linear map, and a "
                 "finite-strain step is not one",
             "0 (the automatic step reads the particles' speeds every step)");
    if (s.time.courant_auto && !doc["time"].contains("safety")) s.time.safety = kFiniteStrainSafety;
    check_initial_gradients(s, doc, fs);
    check_normal_tractions(s, doc);
  }

  static std::string model_path(const MaterialSpec& m) {
    return key_path(key_path("materials", m.name), "model");
  }

  // f(physics, material) with the finite-strain physics of a hyperelastic material in the
  // scene's dimension: the hyperbolic range of each material is its physics' to state.
  template <class F>
  static auto with_hyperelastic_physics(const MaterialSpec& m, int dimension, F&& f) {
    const auto with = [&](auto p) {
      using P = decltype(p);
      return f(p, typename P::Material(m.young, m.poisson, m.density));
    };
    if (std::holds_alternative<Hyperelastic<SaintVenantKirchhoff>>(m.model))
      return dimension == 1 ? with(FiniteStrainBar<SaintVenantKirchhoff>{})
                            : with(FiniteStrainPlane<SaintVenantKirchhoff>{});
    return dimension == 1 ? with(FiniteStrainBar<NeoHookean>{})
                          : with(FiniteStrainPlane<NeoHookean>{});
  }
  // The least uniaxial F_xx and normal nominal stress in the range (a normal load on an
  // unstrained body drives a uniaxial-strain wave, in 2D as in 1D; in 2D oblique waves may fail
  // first).
  static double lowest_f(const MaterialSpec& m, int dimension) {
    return with_hyperelastic_physics(
        m, dimension, [](auto p, const auto& material) { return p.lowest_f(material); });
  }
  static double lowest_stress(const MaterialSpec& m, int dimension) {
    return with_hyperelastic_physics(
        m, dimension, [](auto p, const auto& material) { return p.lowest_stress(material); });
  }
  // 2D: an initial F of positive determinant whose acoustic tensor is positive definite in every
  // in-plane direction (the plane physics' own speed is a number).
  static bool hyperbolic_2d(const MaterialSpec& m, const std::vector<double>& f) {
    const Eigen::Matrix2d g{{f[0], f[1]}, {f[2], f[3]}};
    return g.determinant() > 0 && with_hyperelastic_physics(m, 2, [&](auto p, const auto& mat) {
             if constexpr (decltype(p)::dim == 2)
               return p.state_wave_speed(p.specific(g, Eigen::Vector2d::Zero(), mat), mat) >= 0;
             else
               return false;
           });
  }

  // Bodies of finite-strain materials: a deformation gradient inside the law's range, no stress.
  void check_initial_gradients(const Scene& s, const json& doc, const std::string& fs) const {
    for (std::size_t i = 0; i < s.bodies.size(); ++i) {
      const BodySpec& b = s.bodies[i];
      const MaterialSpec& m = s.materials[b.material];
      const std::string path = index_path("bodies", i);
      for (double x : b.stress)
        if (x != 0)
          refuse(key_path(path, "stress"), doc["bodies"][i]["stress"],
                 "is not allowed " + fs + ": its bodies start from a deformation gradient",
                 "deformation_gradient (the nominal stress follows from it), or no stress key");
      if (b.deformation_gradient.empty()) continue;
      const json& given = doc["bodies"][i]["deformation_gradient"];
      const std::string outside = "is outside the hyperbolic range of \"" +
                                  std::string(m.model_name()) + "\" (material \"" + m.name + "\")";
      if (s.dimension == 2) {
        if (!hyperbolic_2d(m, b.deformation_gradient))
          refuse(key_path(path, "deformation_gradient"), given, outside,
                 "det F > 0 and an acoustic tensor positive definite in every direction");
        continue;
      }
      const double lo = lowest_f(m, 1);
      if (!(b.deformation_gradient[0] > lo))
        refuse(key_path(path, "deformation_gradient"), given, outside,
               "F_xx > " + number_text(lo) +
                   (lo > 0 ? " (the longitudinal tangent dP/dF vanishes at 1/sqrt(3))" : ""));
    }
  }

  // A normal traction no state of the law reaches would compress past the range at the loaded
  // edge.
  void check_normal_tractions(const Scene& s, const json& doc) const {
    double lowest = -std::numeric_limits<double>::infinity();
    const MaterialSpec* limiting = nullptr;
    for (const MaterialSpec& m : s.materials)
      if (const double p = lowest_stress(m, s.dimension); p > lowest) lowest = p, limiting = &m;
    const auto d = static_cast<std::size_t>(s.dimension);
    for (int axis = 0; axis < s.dimension && limiting; ++axis)
      for (int side = 0; side < 2; ++side)
        for (const BoundarySpec& b : s.boundaries[axis][side])
          if (b.kind == BoundaryKind::traction)
            for (std::size_t k = 0; k < b.values.size(); k += d)
              if (!(b.values[k] > lowest)) {
                const std::string key = side_keys[2 * axis + side];
                refuse(key_path("boundaries", key), doc["boundaries"][key],
                       "prescribes a normal nominal stress " + number_text(b.values[k]) +
                           " Pa that \"" + limiting->model_name() + "\" (material \"" +
                           limiting->name + "\") reaches only past its hyperbolic range",
                       "normal nominal stresses above " + number_text(lowest) +
                           " Pa (P_xx at the least uniaxial F_xx in the range, " +
                           number_text(lowest_f(*limiting, s.dimension)) + ")");
              }
  }

  static std::string number_text(double x) {
    std::ostringstream o;
    o << x;
    return o.str();
  }

  [[noreturn]] void fail(const std::string& path, const std::string& text) const {
    throw SceneError(source_ + ": " + (path.empty() ? "(top level)" : path) + ": " + text);
  }

  [[noreturn]] void refuse(const std::string& path, const json& v, const std::string& problem,
                           const std::string& allowed) const {
    fail(path, "value " + show(v) + " " + problem + "; allowed: " + allowed);
  }

  [[noreturn]] void wrong_type(const std::string& path, const json& v,
                               const std::string& allowed) const {
    refuse(path, v, std::string("has the wrong type (") + v.type_name() + ")", allowed);
  }

  [[noreturn]] void not_allowed(const std::string& path, const json& v,
                                const std::string& allowed) const {
    refuse(path, v, "is not allowed", allowed);
  }

  void check_object(const json& v, const std::string& path,
                    std::initializer_list<const char*> keys) const {
    check_object(v, path, std::vector<std::string>(keys.begin(), keys.end()));
  }
  void check_object(const json& v, const std::string& path,
                    const std::vector<std::string>& names) const {
    if (!v.is_object()) wrong_type(path, v, "an object with keys " + join(names));
    for (auto it = v.begin(); it != v.end(); ++it)
      if (std::find(names.begin(), names.end(), it.key()) == names.end())
        fail(key_path(path, it.key()), "unknown key; allowed keys: " + join(names));
  }

  static const json* find(const json& object, const char* key) {
    const auto it = object.find(key);
    return it == object.end() ? nullptr : &*it;
  }

  const json& require(const json& object, const std::string& path, const char* key,
                      const std::string& allowed) const {
    if (const json* v = find(object, key)) return *v;
    fail(key_path(path, key), "missing required key; allowed: " + allowed);
  }

  double number(const json& v, const std::string& path, const std::string& allowed) const {
    if (!v.is_number()) wrong_type(path, v, allowed);
    const double x = v.get<double>();
    if (!std::isfinite(x)) refuse(path, v, "is not a finite number", allowed);
    return x;
  }

  double positive(const json& v, const std::string& path) const {
    const double x = number(v, path, "a number > 0");
    if (!(x > 0)) not_allowed(path, v, "a number > 0");
    return x;
  }

  int integer(const json& v, const std::string& path, long lo, long hi,
              std::string allowed = {}) const {
    if (allowed.empty())
      allowed = "an integer from " + std::to_string(lo) + " to " + std::to_string(hi);
    const double x = number(v, path, allowed);
    if (x != std::floor(x)) refuse(path, v, "is not an integer", allowed);
    if (x < static_cast<double>(lo) || x > static_cast<double>(hi)) not_allowed(path, v, allowed);
    return static_cast<int>(x);
  }

  bool boolean(const json& v, const std::string& path) const {
    if (!v.is_boolean()) wrong_type(path, v, "true or false");
    return v.get<bool>();
  }

  const json& array(const json& v, const std::string& path, const std::string& allowed) const {
    if (!v.is_array()) wrong_type(path, v, allowed);
    return v;
  }

  // An array of exactly n finite numbers, one per axis (or stress component).
  std::vector<double> numbers(const json& v, const std::string& path, std::size_t n,
                              const std::string& what) const {
    const std::string allowed =
        "an array of " + std::to_string(n) + " number" + (n == 1 ? "" : "s") + " (" + what + ")";
    array(v, path, allowed);
    if (v.size() != n) refuse(path, v, "has " + std::to_string(v.size()) + " entries", allowed);
    std::vector<double> out;
    for (std::size_t i = 0; i < n; ++i)
      out.push_back(number(v[i], index_path(path, i), "a number"));
    return out;
  }

  // One of `values`, spelled as to_string spells it (the names printed are the names parsed).
  template <class E>
  E named(const json& v, const std::string& path, std::initializer_list<E> values) const {
    return named_among(v, path, values);
  }
  template <class E, std::size_t N>
  E named(const json& v, const std::string& path, const std::array<E, N>& values) const {
    return named_among(v, path, values);
  }
  template <class Values>
  auto named_among(const json& v, const std::string& path, const Values& values) const {
    using E = std::decay_t<decltype(*std::begin(values))>;
    std::vector<std::pair<const char*, E>> names;
    for (E e : values) names.emplace_back(to_string(e), e);
    return choice_among(v, path, names);
  }

  template <class E>
  E choice(const json& v, const std::string& path, Names<E> names) const {
    return choice_among(v, path, names);
  }

  // The value paired with the name `v` holds; `names`: pairs of name and value.
  template <class NameList>
  auto choice_among(const json& v, const std::string& path, const NameList& names) const {
    std::vector<std::string> listed;
    for (const auto& [name, value] : names) listed.push_back(name);
    if (!v.is_string()) wrong_type(path, v, "one of " + join(listed));
    for (const auto& [name, value] : names)
      if (v.get<std::string>() == name) return value;
    refuse(path, v, "is not known", "one of " + join(listed));
  }

  int parse_dimension(const json& v) const {
    if (v.is_number() && v.get<double>() == 3)
      refuse("dimension", v, "is not allowed: 3D is not implemented yet", "1 or 2");
    return integer(v, "dimension", 1, 2, "1 or 2");
  }

  GridSpec parse_grid(const json& g, int dim) const {
    check_object(g, "grid", {"origin", "cell_size", "cells", "periodic"});
    const auto n = static_cast<std::size_t>(dim);
    const std::string per_axis = "one per axis, dimension " + std::to_string(dim);
    GridSpec grid;
    grid.origin = numbers(require(g, "grid", "origin", "an array of numbers, one per axis"),
                          "grid.origin", n, per_axis);
    const json& h = require(g, "grid", "cell_size", "an array of numbers > 0, one per axis");
    grid.cell_size = numbers(h, "grid.cell_size", n, per_axis);
    for (std::size_t a = 0; a < n; ++a) positive(h[a], index_path("grid.cell_size", a));
    const json& c = require(g, "grid", "cells", "an array of integers >= 1, one per axis");
    numbers(c, "grid.cells", n, per_axis);
    for (std::size_t a = 0; a < n; ++a)
      grid.cells.push_back(integer(c[a], index_path("grid.cells", a), 1, INT_MAX));
    // Every cell has 2^dim nodes of its own (broken shape functions), counted in an int.
    double nodes = std::pow(2.0, static_cast<double>(n));
    for (int k : grid.cells) nodes *= k;
    if (nodes > INT_MAX)
      refuse("grid.cells", c, "makes " + format_number(nodes) + " nodes, more than 2^31 - 1",
             "at most 2^31 - 1 nodes, 2^dimension per cell");
    if (const json* p = find(g, "periodic")) {
      const std::string allowed =
          "true or false, or an array of " + std::to_string(dim) + " booleans (one per axis)";
      if (p->is_boolean()) {
        for (std::size_t a = 0; a < n; ++a) grid.periodic[a] = p->get<bool>();
      } else if (p->is_array()) {
        if (p->size() != n)
          refuse("grid.periodic", *p, "has " + std::to_string(p->size()) + " entries", allowed);
        for (std::size_t a = 0; a < n; ++a)
          grid.periodic[a] = boolean((*p)[a], index_path("grid.periodic", a));
      } else {
        wrong_type("grid.periodic", *p, allowed);
      }
    }
    return grid;
  }

  std::vector<MaterialSpec> parse_materials(const json& m) const {
    if (!m.is_object())
      wrong_type("materials", m, "an object of materials, e.g. {\"steel\": {...}}");
    if (m.empty()) refuse("materials", m, "holds no material", "at least one material");
    std::vector<MaterialSpec> out;
    for (auto it = m.begin(); it != m.end(); ++it) {
      const std::string path = key_path("materials", it.key());
      const json& v = it.value();
      MaterialSpec mat;
      mat.name = it.key();
      std::size_t model = 0;  // linear_elastic
      if (const json* k = find(v, "model")) {
        std::vector<std::pair<const char*, std::size_t>> names;
        for (std::size_t i = 0; i < model_names.size(); ++i) names.emplace_back(model_names[i], i);
        model = choice_among(*k, key_path(path, "model"), names);
      }
      std::vector<std::string> keys = {"model", "young", "poisson", "density"};
      keys.insert(keys.end(), model_parsers[model].keys.begin(), model_parsers[model].keys.end());
      check_object(v, path, keys);
      mat.model = (this->*model_parsers[model].parse)(v, path);
      mat.young = positive(require(v, path, "young", "a number > 0"), key_path(path, "young"));
      mat.density =
          positive(require(v, path, "density", "a number > 0"), key_path(path, "density"));
      if (const json* nu = find(v, "poisson")) {
        const std::string allowed = "-1 < poisson < 0.5";
        mat.poisson = number(*nu, key_path(path, "poisson"), allowed);
        if (!physics::admissible_poisson(mat.poisson))
          not_allowed(key_path(path, "poisson"), *nu, allowed);
      }
      out.push_back(mat);
    }
    return out;
  }

  // What a model reads beside the elastic constants.
  template <class Model>
  MaterialModel read_model(const json& v, const std::string& path) const {
    if constexpr (std::is_same_v<Model, ElastoPlastic>)
      return ElastoPlastic{parse_flow(v, path, false)};
    else if constexpr (std::is_same_v<Model, ElastoViscoplastic>)
      return ElastoViscoplastic{parse_flow(v, path, true)};
    else
      return Model{};
  }
  // One parser per material model (in the order of MaterialModel and model_names): its keys
  // beside the elastic constants, and what it reads of them.
  struct ModelParser {
    std::vector<const char*> keys;
    MaterialModel (Parser::*parse)(const json& v, const std::string& path) const;
  };
  static inline const std::array<ModelParser, std::variant_size_v<MaterialModel>> model_parsers{{
      {{}, &Parser::read_model<LinearElastic>},
      {{"yield_stress", "isotropic_hardening", "kinematic_hardening"},
       &Parser::read_model<ElastoPlastic>},
      {{"yield_stress", "isotropic_hardening", "kinematic_hardening", "relaxation_time",
        "rate_exponent"},
       &Parser::read_model<ElastoViscoplastic>},
      {{}, &Parser::read_model<Hyperelastic<SaintVenantKirchhoff>>},
      {{}, &Parser::read_model<Hyperelastic<NeoHookean>>},
  }};

  // The yield stress, hardening moduli and (viscoplastic) relaxation of a plastic material.
  PlasticFlow parse_flow(const json& v, const std::string& path, bool viscous) const {
    PlasticFlow flow;
    flow.yield_stress = positive(require(v, path, "yield_stress", "a number > 0 (Pa)"),
                                 key_path(path, "yield_stress"));
    for (const auto& [key, modulus] : {std::pair{"isotropic_hardening", &flow.isotropic_hardening},
                                       std::pair{"kinematic_hardening", &flow.kinematic_hardening}})
      if (const json* h = find(v, key)) {
        const std::string allowed = "a number >= 0 (Pa)";
        *modulus = number(*h, key_path(path, key), allowed);
        if (!PlasticFlow::admissible_hardening(*modulus))
          refuse(key_path(path, key), *h,
                 "is not allowed: softening (a negative hardening modulus) makes the local "
                 "problem ill-posed (strain localises in one cell, the result depends on the grid)",
                 allowed);
      }
    if (viscous) {
      flow.relaxation_time = positive(require(v, path, "relaxation_time", "a number > 0 (s)"),
                                      key_path(path, "relaxation_time"));
      if (const json* n = find(v, "rate_exponent")) {
        const std::string allowed =
            "a number >= 1 (the implicit return's Newton iteration relies on a convex rate law)";
        flow.rate_exponent = number(*n, key_path(path, "rate_exponent"), allowed);
        if (!PlasticFlow::admissible_rate_exponent(flow.rate_exponent))
          not_allowed(key_path(path, "rate_exponent"), *n, allowed);
      }
    }
    return flow;
  }

  TimeSpec parse_time(const json& t) const {
    check_object(t, "time",
                 {"end", "integrator", "courant", "criterion", "growth_budget", "check_scene_every",
                  "safety", "blow_up_check", "blow_up_factor", "max_steps"});
    TimeSpec time;
    time.end = positive(require(t, "time", "end", "a number > 0"), "time.end");
    if (const json* i = find(t, "integrator"))
      time.integrator = named(*i, "time.integrator", time_schemes);
    if (const json* c = find(t, "courant")) {
      const std::string allowed = "a number > 0 or \"auto\"";
      if (c->is_string()) {
        if (c->get<std::string>() != "auto") not_allowed("time.courant", *c, allowed);
        time.courant_auto = true;
      } else {
        time.courant = number(*c, "time.courant", allowed);
        if (!(time.courant > 0)) not_allowed("time.courant", *c, allowed);
      }
    }
    const std::string only_auto = "only with \"courant\": \"auto\"";
    if (const json* c = find(t, "criterion")) {
      if (!time.courant_auto)
        refuse("time.criterion", *c, "is not allowed without \"courant\": \"auto\"", only_auto);
      time.criterion =
          named(*c, "time.criterion", {Criterion::budget, Criterion::l2, Criterion::monotone});
    }
    if (const json* g = find(t, "growth_budget")) {
      if (!time.courant_auto || time.criterion != Criterion::budget)
        refuse("time.growth_budget", *g, "is not allowed without the budget criterion",
               "only with \"courant\": \"auto\" and \"criterion\": \"budget\" (the default)");
      const std::string allowed = "a factor > 1 (the most a mode may grow over the run)";
      time.growth_budget = number(*g, "time.growth_budget", allowed);
      if (!(time.growth_budget > 1 && std::isfinite(time.growth_budget)))
        not_allowed("time.growth_budget", *g, allowed);
    }
    if (const json* g = find(t, "check_scene_every")) {
      const std::string allowed = "an integer number of steps >= 1 (0: never)";
      if (!time.courant_auto)
        refuse("time.check_scene_every", *g, "is not allowed without \"courant\": \"auto\"",
               only_auto);
      const double every = number(*g, "time.check_scene_every", allowed);
      if (!(every >= 0 && every <= 1e12 && every == std::floor(every)))
        not_allowed("time.check_scene_every", *g, allowed);
      time.check_scene_every = static_cast<long>(every);
    }
    if (const json* s = find(t, "safety")) {
      if (!time.courant_auto)
        refuse("time.safety", *s, "is not allowed without \"courant\": \"auto\"", only_auto);
      const std::string allowed = "0 < safety <= 1";
      time.safety = number(*s, "time.safety", allowed);
      if (!(time.safety > 0 && time.safety <= 1)) not_allowed("time.safety", *s, allowed);
    }
    if (const json* m = find(t, "max_steps")) {
      const std::string allowed = "an integer >= 1 (at most 9.2e18)";
      const double v = number(*m, "time.max_steps", allowed);
      if (!(v >= 1 && v < 9.2e18 && v == std::floor(v))) not_allowed("time.max_steps", *m, allowed);
      time.max_steps = static_cast<long>(v);
    }
    if (const json* b = find(t, "blow_up_check")) {
      if (!b->is_boolean()) not_allowed("time.blow_up_check", *b, "true or false");
      time.blow_up_check = b->get<bool>();
    }
    if (const json* f = find(t, "blow_up_factor")) {
      const std::string allowed = "a number > 1 (energy over initial energy plus load work)";
      time.blow_up_factor = number(*f, "time.blow_up_factor", allowed);
      if (!(time.blow_up_factor > 1 && std::isfinite(time.blow_up_factor)))
        not_allowed("time.blow_up_factor", *f, allowed);
      if (!time.blow_up_check)
        refuse("time.blow_up_factor", *f, "is not allowed with \"blow_up_check\": false",
               "only with the check on");
    }
    return time;
  }

  std::vector<BodySpec> parse_bodies(const json& b, const Scene& s) const {
    array(b, "bodies", "an array of bodies");
    if (b.empty()) refuse("bodies", b, "holds no body", "at least one body");
    std::vector<BodySpec> out;
    for (std::size_t i = 0; i < b.size(); ++i)
      out.push_back(parse_body(b[i], index_path("bodies", i), s));
    return out;
  }

  BodySpec parse_body(const json& b, const std::string& path, const Scene& s) const {
    check_object(b, path,
                 {"material", "box", "particles_per_cell", "positions_in_cell", "masses_in_cell",
                  "velocity", "stress", "deformation_gradient"});
    BodySpec body;
    const auto n = static_cast<std::size_t>(s.dimension);
    const std::string per_axis = "one per axis, dimension " + std::to_string(s.dimension);
    body.material = parse_body_material(b, path, s);
    parse_box(b, path, s, body);
    body.layout = parse_layout(b, path, n);
    const std::size_t layout = body.layout.size();
    body.masses_in_cell.assign(layout, 1.0);
    if (const json* w = find(b, "masses_in_cell")) {
      const std::string w_path = key_path(path, "masses_in_cell");
      body.masses_in_cell =
          numbers(*w, w_path, layout, "numbers > 0, one per particle of the cell layout");
      for (std::size_t j = 0; j < layout; ++j) positive((*w)[j], index_path(w_path, j));
    }
    body.velocity.assign(n, 0.0);
    if (const json* v = find(b, "velocity"))
      body.velocity = numbers(*v, key_path(path, "velocity"), n, per_axis);
    const std::size_t ns = stress_size(s.dimension);
    body.stress.assign(ns, 0.0);
    if (const json* st = find(b, "stress"))
      body.stress = numbers(*st, key_path(path, "stress"), ns,
                            s.dimension == 1 ? "sigma" : "independent stress components");
    if (const json* f = find(b, "deformation_gradient"))
      body.deformation_gradient =
          s.dimension == 1
              ? numbers(*f, key_path(path, "deformation_gradient"), 1, "[F_xx]")
              : numbers(*f, key_path(path, "deformation_gradient"), 4, "[F_xx, F_xy, F_yx, F_yy]");
    return body;
  }

  // The index of the body's material among the scene's.
  int parse_body_material(const json& b, const std::string& path, const Scene& s) const {
    std::vector<std::string> names;
    for (const auto& m : s.materials) names.push_back(m.name);
    const std::string material_path = key_path(path, "material");
    const json& m = require(b, path, "material", "one of " + join(names));
    if (!m.is_string()) wrong_type(material_path, m, "one of " + join(names));
    const auto it = std::find(names.begin(), names.end(), m.get<std::string>());
    if (it == names.end())
      refuse(material_path, m, "is not a material of this scene", "one of " + join(names));
    return static_cast<int>(it - names.begin());
  }

  // The body's box: inside the grid, max above min on every axis.
  void parse_box(const json& b, const std::string& path, const Scene& s, BodySpec& body) const {
    const auto n = static_cast<std::size_t>(s.dimension);
    const std::string per_axis = "one per axis, dimension " + std::to_string(s.dimension);
    const std::string box_path = key_path(path, "box");
    const json& box = require(b, path, "box", "an object with min and max");
    check_object(box, box_path, {"min", "max"});
    const json& lo = require(box, box_path, "min", "an array of numbers, one per axis");
    const json& hi = require(box, box_path, "max", "an array of numbers, one per axis");
    const std::string min_path = key_path(box_path, "min"), max_path = key_path(box_path, "max");
    body.box_min = numbers(lo, min_path, n, per_axis);
    body.box_max = numbers(hi, max_path, n, per_axis);
    std::string grid_text;
    std::vector<double> grid_lo, grid_hi;
    for (std::size_t a = 0; a < n; ++a) {
      grid_lo.push_back(s.grid.origin[a]);
      grid_hi.push_back(s.grid.origin[a] + s.grid.cells[a] * s.grid.cell_size[a]);
      grid_text +=
          (a ? " x [" : "[") + format_number(grid_lo[a]) + ", " + format_number(grid_hi[a]) + "]";
    }
    for (std::size_t a = 0; a < n; ++a) {
      if (!(body.box_min[a] < body.box_max[a]))
        refuse(max_path, hi,
               "is not above " + key_path(box_path, "min") + " " + show(lo) + " on axis " +
                   axis_names[a],
               "max > min on every axis");
      // Rounding slack: a box drawn up to the grid's end must not be refused.
      const double slack = 1e-12 * (grid_hi[a] - grid_lo[a]);
      if (body.box_min[a] < grid_lo[a] - slack)
        refuse(min_path, lo, "is outside the grid " + grid_text, "inside the grid");
      if (body.box_max[a] > grid_hi[a] + slack)
        refuse(max_path, hi, "is outside the grid " + grid_text, "inside the grid");
    }
  }

  // Local coordinates of a cell's particles: particles_per_cell or positions_in_cell.
  std::vector<std::array<double, 3>> parse_layout(const json& b, const std::string& path,
                                                  std::size_t n) const {
    std::vector<std::array<double, 3>> layout;
    const json* ppc = find(b, "particles_per_cell");
    const json* pic = find(b, "positions_in_cell");
    const std::string ppc_path = key_path(path, "particles_per_cell");
    const std::string pic_path = key_path(path, "positions_in_cell");
    const std::string one_of = "exactly one of particles_per_cell and positions_in_cell";
    if (ppc && pic)
      refuse(pic_path, *pic, "is given together with particles_per_cell " + show(*ppc), one_of);
    if (!ppc && !pic)
      fail(ppc_path, "missing required key (or positions_in_cell); allowed: " + one_of);
    if (ppc) {
      std::array<int, 3> count{1, 1, 1};
      const std::string allowed = "an integer from 1 to " + std::to_string(max_particles_per_cell) +
                                  " (per axis), or an array of " + std::to_string(n) +
                                  " such integers, at most " +
                                  std::to_string(max_particles_per_cell) + " particles in all";
      int total = 1;
      for (std::size_t a = 0; a < n; ++a) {
        const json& c = ppc->is_array() && ppc->size() == n ? (*ppc)[a] : *ppc;
        if (ppc->is_array() && ppc->size() != n)
          refuse(ppc_path, *ppc, "has " + std::to_string(ppc->size()) + " entries", allowed);
        count[a] = integer(c, ppc->is_array() ? index_path(ppc_path, a) : ppc_path, 1,
                           max_particles_per_cell, allowed);
        total *= count[a];
      }
      if (total > max_particles_per_cell)
        refuse(ppc_path, *ppc, "makes " + std::to_string(total) + " particles per cell", allowed);
      for (int k = 0; k < count[1] * count[2]; ++k)
        for (int i = 0; i < count[0]; ++i) {
          std::array<double, 3> xi{};
          const int j = k % count[1], l = k / count[1];
          xi[0] = (i + 0.5) / count[0];
          if (n > 1) xi[1] = (j + 0.5) / count[1];
          if (n > 2) xi[2] = (l + 0.5) / count[2];
          layout.push_back(xi);
        }
    } else {
      const std::string point =
          n == 1 ? "a number in [0, 1]" : "an array of " + std::to_string(n) + " numbers in [0, 1]";
      const std::string allowed = "an array of 1 to " + std::to_string(max_particles_per_cell) +
                                  (n == 1 ? " numbers in [0, 1]" : " points, each " + point);
      array(*pic, pic_path, allowed);
      if (pic->empty() || pic->size() > max_particles_per_cell)
        refuse(pic_path, *pic, "has " + std::to_string(pic->size()) + " entries", allowed);
      for (std::size_t j = 0; j < pic->size(); ++j) {
        const std::string p = index_path(pic_path, j);
        std::array<double, 3> xi{};
        if (n == 1) {
          xi[0] = number((*pic)[j], p, point);
          if (!(xi[0] >= 0 && xi[0] <= 1)) not_allowed(p, (*pic)[j], point);
        } else {
          const auto coords = numbers((*pic)[j], p, n, "local coordinates in [0, 1]");
          for (std::size_t a = 0; a < n; ++a) {
            xi[a] = coords[a];
            if (!(xi[a] >= 0 && xi[a] <= 1))
              not_allowed(index_path(p, a), (*pic)[j][a], "a number in [0, 1]");
          }
        }
        layout.push_back(xi);
      }
    }
    return layout;
  }

  // Every body holds a particle; no particle lies in two boxes.
  void check_seeds(const Scene& s, const json& bodies) const {
    const auto nb = s.bodies.size();
    const auto dim = static_cast<std::size_t>(s.dimension);
    for (std::size_t i = 0; i < nb; ++i) {
      const BodySpec& b = s.bodies[i];
      bool any = false;
      for_each_seed(s, b, box_cells(s, b.box_min, b.box_max), [&](const Seed&) {
        any = true;
        return false;
      });
      if (any) continue;
      std::string layout;
      for (const auto& xi : b.layout) {
        std::vector<double> point(xi.begin(), xi.begin() + static_cast<std::ptrdiff_t>(dim));
        layout +=
            (layout.empty() ? "" : ", ") + (dim == 1 ? format_number(xi[0]) : numbers_text(point));
      }
      refuse(index_path("bodies", i) + ".box", bodies[i]["box"],
             "holds no particle: no origin + (k + xi) * cell_size with xi in [" + layout +
                 "] lies in [min, max)",
             "a box holding at least one particle");
    }
    // Pairs whose boxes can meet, by a sweep along x (n log n plus the pairs that overlap in x,
    // not all n^2 pairs): bodies in order of box_min[0], each against those still open.
    std::vector<std::size_t> order(nb);
    for (std::size_t k = 0; k < nb; ++k) order[k] = k;
    std::sort(order.begin(), order.end(), [&](std::size_t a, std::size_t b) {
      return s.bodies[a].box_min[0] < s.bodies[b].box_min[0] ||
             (s.bodies[a].box_min[0] == s.bodies[b].box_min[0] && a < b);
    });
    std::vector<std::pair<std::size_t, std::size_t>> candidates;  // (i, j), i < j
    std::vector<std::size_t> open;
    for (std::size_t j : order) {
      std::erase_if(
          open, [&](std::size_t i) { return s.bodies[i].box_max[0] <= s.bodies[j].box_min[0]; });
      for (std::size_t i : open) candidates.emplace_back(std::min(i, j), std::max(i, j));
      open.push_back(j);
    }
    std::sort(candidates.begin(), candidates.end(), [](const auto& a, const auto& b) {
      return a.second < b.second || (a.second == b.second && a.first < b.first);
    });
    for (const auto& [i, j] : candidates) {
      {
        std::vector<double> lo(dim), hi(dim);
        bool meet = true;
        for (std::size_t a = 0; a < dim; ++a) {
          lo[a] = std::max(s.bodies[i].box_min[a], s.bodies[j].box_min[a]);
          hi[a] = std::min(s.bodies[i].box_max[a], s.bodies[j].box_max[a]);
          if (!(lo[a] < hi[a])) meet = false;
        }
        if (!meet) continue;
        // A seed of body p inside body q's box: only the cells of the two boxes' intersection.
        for (const auto& pq : {std::pair{i, j}, std::pair{j, i}}) {
          const auto p = pq.first, q = pq.second;  // not bindings: clang 14 cannot capture them
          std::optional<Seed> shared;
          for_each_seed(s, s.bodies[p], box_cells(s, lo, hi), [&](const Seed& seed) {
            for (std::size_t a = 0; a < dim; ++a)
              if (!(s.bodies[q].box_min[a] <= seed.x[a] && seed.x[a] < s.bodies[q].box_max[a]))
                return true;
            shared = seed;
            return false;
          });
          if (!shared) continue;
          std::string cell_text;
          std::vector<double> x;
          for (std::size_t a = 0; a < dim; ++a) {
            cell_text += (a ? ", " : "") + std::to_string(shared->cell[a]);
            x.push_back(shared->x[a]);
          }
          refuse(index_path("bodies", j) + ".box", bodies[j]["box"],
                 "overlaps bodies[" + std::to_string(i) + "].box: both claim the particle of " +
                     index_path("bodies", p) +
                     " at x = " + (x.size() == 1 ? format_number(x[0]) : numbers_text(x)) +
                     " (cell " + cell_text + ")",
                 "boxes that share no particle");
        }
      }
    }
  }

  void parse_boundaries(const json& b, Scene& s) const {
    std::vector<std::string> sides(side_keys, side_keys + 2 * s.dimension);
    if (!b.is_object()) wrong_type("boundaries", b, "an object with keys " + join(sides));
    for (auto it = b.begin(); it != b.end(); ++it) {
      const std::string path = key_path("boundaries", it.key());
      const auto* k = std::find(std::begin(side_keys), std::end(side_keys), it.key());
      const auto index = static_cast<int>(k - std::begin(side_keys));
      if (k == std::end(side_keys)) fail(path, "unknown key; allowed keys: " + join(sides));
      if (index >= 2 * s.dimension)
        fail(path,
             "unknown key in " + std::to_string(s.dimension) + "D; allowed keys: " + join(sides));
      const int axis = index / 2;
      if (s.grid.periodic[static_cast<std::size_t>(axis)])
        refuse(path, it.value(), "is not allowed on a periodic axis",
               std::string("no boundaries entry for axis ") + axis_names[axis] +
                   " when grid.periodic is true on it");
      auto& segments = s.boundaries[axis][index % 2];
      const json& v = it.value();
      if (v.is_array() && s.dimension > 1) {
        if (v.empty())
          refuse(path, v, "holds no segment", "a condition object or an array of segments");
        for (std::size_t j = 0; j < v.size(); ++j)
          segments.push_back(parse_boundary(v[j], index_path(path, j), s, axis));
        check_segments(segments, path, v, s, axis);
      } else {
        const std::string allowed = s.dimension == 1
                                        ? "an object with type (and value)"
                                        : "an object with type (value, range) or an array of them";
        if (!v.is_object()) wrong_type(path, v, allowed);
        segments.push_back(parse_boundary(v, path, s, axis));
        if (segments.back().has_range) check_segments(segments, path, v, s, axis);
      }
    }
  }

  // Ranges inside the side and disjoint (touching is allowed); sorted along the side.
  void check_segments(std::vector<BoundarySpec>& segments, const std::string& path, const json& v,
                      const Scene& s, int axis) const {
    const auto t = static_cast<std::size_t>(1 - axis);  // the side's tangential axis (2D)
    const double lo = s.grid.origin[t], hi = s.grid.upper(t);
    const double slack = 1e-12 * (hi - lo);
    const std::string side_text = std::string("the side's extent along ") + axis_names[t] + " [" +
                                  format_number(lo) + ", " + format_number(hi) + "]";
    for (std::size_t j = 0; j < segments.size(); ++j) {
      const BoundarySpec& b = segments[j];
      const std::string rpath = (v.is_array() ? index_path(path, j) : path) + ".range";
      if (!b.has_range)
        fail(rpath, "missing required key for a segment in a list; allowed: [from, to] within " +
                        side_text);
      if (b.range_lo < lo - slack || b.range_hi > hi + slack)
        refuse(rpath, v.is_array() ? v[j].at("range") : v.at("range"), "is outside " + side_text,
               "[from, to] within " + side_text);
    }
    std::vector<std::size_t> order(segments.size());
    for (std::size_t j = 0; j < order.size(); ++j) order[j] = j;
    std::sort(order.begin(), order.end(), [&](std::size_t a, std::size_t b) {
      return segments[a].range_lo < segments[b].range_lo;
    });
    for (std::size_t j = 1; j < order.size(); ++j) {
      const BoundarySpec &prev = segments[order[j - 1]], &next = segments[order[j]];
      if (next.range_lo < prev.range_hi)
        refuse(index_path(path, order[j]) + ".range", v[order[j]].at("range"),
               "overlaps " + index_path(path, order[j - 1]) + ".range " +
                   show(v[order[j - 1]].at("range")),
               "segments that do not overlap (they may touch)");
    }
    std::vector<BoundarySpec> sorted;
    for (std::size_t j : order) sorted.push_back(segments[j]);
    segments = sorted;
  }

  BoundarySpec parse_boundary(const json& v, const std::string& path, const Scene& s,
                              int axis) const {
    const bool plane = s.dimension > 1;
    if (plane)
      check_object(v, path, {"type", "value", "range"});
    else
      check_object(v, path, {"type", "value"});
    BoundarySpec bc;
    const std::string type_path = key_path(path, "type");
    if (plane)
      bc.kind = named(require(v, path, "type", "one of free, fixed, traction, velocity, roller"),
                      type_path,
                      {BoundaryKind::free, BoundaryKind::fixed, BoundaryKind::traction,
                       BoundaryKind::velocity, BoundaryKind::roller});
    else
      bc.kind = named(require(v, path, "type", "one of free, fixed, traction, velocity"), type_path,
                      {BoundaryKind::free, BoundaryKind::fixed, BoundaryKind::traction,
                       BoundaryKind::velocity});
    if (const json* r = find(v, "range")) {
      const auto range = numbers(*r, key_path(path, "range"), 2,
                                 std::string("metres along ") + axis_names[1 - axis]);
      if (!(range[0] < range[1]))
        refuse(key_path(path, "range"), *r, "is empty or reversed", "[from, to] with from < to");
      bc.has_range = true;
      bc.range_lo = range[0];
      bc.range_hi = range[1];
    }
    const std::string value_path = key_path(path, "value");
    const auto n = static_cast<std::size_t>(s.dimension);
    const std::string what =
        bc.kind == BoundaryKind::velocity
            ? (plane ? "v_x, v_y" : "v")
            : (plane ? (axis == 0 ? "sigma_xx, sigma_xy" : "sigma_yy, sigma_xy") : "sigma");
    const std::string one = plane ? "[" + what + "]" : "a number";
    const std::string allowed = one + " or a table [[t0, " + (plane ? one : "v0") + "], [t1, " +
                                (plane ? one : "v1") + "], ...]";
    const json* value = find(v, "value");
    const bool needs_value = bc.kind == BoundaryKind::traction || bc.kind == BoundaryKind::velocity;
    if (!needs_value) {
      if (value)
        refuse(value_path, *value,
               std::string("is not allowed with type \"") + dgmpm::to_string(bc.kind) + "\"",
               plane ? "no value for free, fixed and roller" : "no value for free and fixed ends");
      return bc;
    }
    if (!value)
      fail(value_path, std::string("missing required key for type \"") + dgmpm::to_string(bc.kind) +
                           "\"; allowed: " + allowed);
    // A constant: a number (1D) or an array of numbers (2D).
    const bool constant = plane ? (value->is_array() && !value->empty() && (*value)[0].is_number())
                                : value->is_number();
    if (constant) {
      bc.times = {0.0};
      bc.values = plane ? numbers(*value, value_path, n, what)
                        : std::vector<double>{number(*value, value_path, allowed)};
      return bc;
    }
    parse_value_table(*value, value_path, plane ? n : 1, what, one, allowed, bc);
    return bc;
  }

  // A boundary value's table [[t0, value0], ...]: times from 0, strictly increasing; `n` numbers
  // per time (an array of them in 2D).
  void parse_value_table(const json& table, const std::string& value_path, std::size_t n,
                         const std::string& what, const std::string& one,
                         const std::string& allowed, BoundarySpec& bc) const {
    const bool plane = n > 1;
    if (!table.is_array()) wrong_type(value_path, table, allowed);
    if (table.empty()) refuse(value_path, table, "is an empty table", allowed);
    for (std::size_t k = 0; k < table.size(); ++k) {
      const std::string row = index_path(value_path, k);
      const json& r = table[k];
      const std::string row_allowed = plane ? "a pair [time, " + one + "]" : "a pair [time, value]";
      array(r, row, row_allowed);
      if (r.size() != 2)
        refuse(row, r, "has " + std::to_string(r.size()) + " entries", row_allowed);
      const double time = number(r[0], row + "[0]", "a time >= 0");
      if (k == 0 && !(time >= 0)) refuse(row + "[0]", r[0], "is a negative time", "times >= 0");
      if (k > 0 && !(time > bc.times.back()))
        refuse(row + "[0]", r[0],
               "is not after the previous time " + format_number(bc.times.back()),
               "strictly increasing times");
      bc.times.push_back(time);
      if (plane) {
        for (double x : numbers(r[1], row + "[1]", n, what)) bc.values.push_back(x);
      } else {
        bc.values.push_back(number(r[1], row + "[1]", "a number"));
      }
    }
  }

  Scene::PlaneWave parse_plane_wave(const json& w, const Scene& s) const {
    if (s.dimension != 2)
      refuse("plane_wave", w, "is not allowed in " + std::to_string(s.dimension) + "D",
             "plane_wave in 2D scenes");
    if (!s.grid.periodic[0] || !s.grid.periodic[1])
      refuse("plane_wave", w, "needs a grid periodic on both axes", "\"periodic\": true in grid");
    check_object(w, "plane_wave", {"wave", "cycles", "amplitude"});
    Scene::PlaneWave wave;
    wave.shear = choice<int>(require(w, "plane_wave", "wave", "\"p\" or \"s\""), "plane_wave.wave",
                             {{"p", 0}, {"s", 1}}) == 1;
    const std::string allowed = "an array of 2 integers, not both 0 (wave periods across the grid)";
    const json& c = require(w, "plane_wave", "cycles", allowed);
    numbers(c, "plane_wave.cycles", 2, "wave periods across the grid along x and y");
    for (std::size_t a = 0; a < 2; ++a)
      wave.cycles[a] = integer(c[a], index_path("plane_wave.cycles", a), -1000, 1000, allowed);
    if (wave.cycles[0] == 0 && wave.cycles[1] == 0) not_allowed("plane_wave.cycles", c, allowed);
    wave.amplitude = positive(require(w, "plane_wave", "amplitude", "a velocity > 0 (m/s)"),
                              "plane_wave.amplitude");
    return wave;
  }

  void parse_output(const json& o, Scene& s) const {
    check_object(o, "output", {"directory", "times", "formats", "land", "vtu_encoding"});
    if (const json* l = find(o, "land")) s.output.land = boolean(*l, "output.land");
    if (const json* e = find(o, "vtu_encoding"))
      s.output.vtu_binary =
          choice<int>(*e, "output.vtu_encoding", {{"binary", 1}, {"ascii", 0}}) == 1;
    if (const json* f = find(o, "formats")) {
      const std::string allowed = "an array of one or both of \"csv\", \"vtu\"";
      array(*f, "output.formats", allowed);
      if (f->empty()) refuse("output.formats", *f, "is empty", allowed);
      s.output.csv = s.output.vtu = false;
      for (std::size_t k = 0; k < f->size(); ++k) {
        const std::string p = index_path("output.formats", k);
        bool& on =
            choice<int>((*f)[k], p, {{"csv", 0}, {"vtu", 1}}) == 0 ? s.output.csv : s.output.vtu;
        if (on) refuse(p, (*f)[k], "is listed twice", "each format once");
        on = true;
      }
    }
    if (const json* d = find(o, "directory")) {
      if (!d->is_string()) wrong_type("output.directory", *d, "a non-empty path");
      if (d->get<std::string>().empty()) not_allowed("output.directory", *d, "a non-empty path");
      s.output.directory = d->get<std::string>();
    }
    if (const json* t = find(o, "times")) {
      const std::string allowed = "times t with 0 < t <= time.end = " + format_number(s.time.end);
      array(*t, "output.times", "an array of " + allowed);
      std::vector<std::pair<double, std::size_t>> times;  // (time, index): n log n, not n^2
      for (std::size_t k = 0; k < t->size(); ++k) {
        const std::string p = index_path("output.times", k);
        const double x = number((*t)[k], p, allowed);
        if (!(x > 0 && x <= s.time.end)) not_allowed(p, (*t)[k], allowed);
        times.emplace_back(x, k);
      }
      std::sort(times.begin(), times.end());
      for (std::size_t k = 1; k < times.size(); ++k)
        if (times[k].first == times[k - 1].first) {
          const std::size_t second = std::max(times[k].second, times[k - 1].second);
          refuse(index_path("output.times", second), (*t)[second], "is listed twice",
                 "distinct times");
        }
      s.output.times.clear();
      for (const auto& [x, k] : times) s.output.times.push_back(x);
    }
  }
};

}  // namespace

Scene parse_scene(const nlohmann::json& document, const std::string& source) {
  Scene scene = Parser(source).parse(document);
  scene.document = document;
  return scene;
}

Scene load_scene(const std::string& path) {
  std::error_code ec;
  if (std::filesystem::is_directory(path, ec))
    throw SceneError(path + ": cannot read the scene: it is a directory");
  // Only a regular file of bounded size: a FIFO would block, /dev/zero would never end.
  constexpr std::uintmax_t kMaxSceneBytes = 64u << 20;
  if (std::filesystem::exists(path, ec) && !std::filesystem::is_regular_file(path, ec))
    throw SceneError(path + ": cannot read the scene: not a regular file (a device, FIFO or "
                            "socket); allowed: a JSON file");
  if (const auto size = std::filesystem::file_size(path, ec); !ec && size > kMaxSceneBytes)
    throw SceneError(path + ": cannot read the scene: " + std::to_string(size) +
                     " bytes, more than the 64 MiB a scene may take");
  std::ifstream in(path, std::ios::binary);
  if (!in) throw SceneError(path + ": cannot read the scene: " + std::strerror(errno));
  std::ostringstream text;
  text << in.rdbuf();
  if (in.bad()) throw SceneError(path + ": cannot read the scene: read error");
  Scene scene = parse_scene_text(text.str(), path);
  // A relative output directory belongs to the scene, wherever the run is started from.
  auto& dir = scene.output.directory;
  if (!dir.empty() && std::filesystem::path(dir).is_relative())
    dir = (std::filesystem::path(path).parent_path() / dir).lexically_normal().string();
  return scene;
}

Scene parse_scene_text(const std::string& raw, const std::string& path) {
  // nlohmann keeps the last of duplicated keys silently; a scene written by hand must not.
  struct Frame {
    bool array;
    std::string key;
    std::size_t index = 0;
    std::set<std::string> keys;
  };
  std::vector<Frame> stack;
  const auto on_event = [&](int, json::parse_event_t event, json& parsed) {
    switch (event) {
      case json::parse_event_t::object_start:
        stack.push_back({false, {}, 0, {}});
        break;
      case json::parse_event_t::array_start:
        stack.push_back({true, {}, 0, {}});
        break;
      case json::parse_event_t::key: {
        Frame& top = stack.back();
        top.key = parsed.get<std::string>();
        if (!top.keys.insert(top.key).second) {
          std::string where;
          for (const Frame& f : stack)
            where = f.array ? index_path(where, f.index) : key_path(where, f.key);
          throw SceneError(path + ": " + where + ": duplicate key; allowed: each key once");
        }
        break;
      }
      case json::parse_event_t::object_end:
      case json::parse_event_t::array_end:
        stack.pop_back();
        [[fallthrough]];
      case json::parse_event_t::value:
        if (!stack.empty() && stack.back().array) ++stack.back().index;
        break;
    }
    return true;
  };
  json document;
  try {
    document = json::parse(raw, on_event);
  } catch (const json::exception& e) {
    // Where: the key being read and, for a syntax error or a number too large for a double, its
    // line and column.
    std::string where;
    for (const Frame& f : stack)
      where = f.array ? index_path(where, f.index) : key_path(where, f.key);
    std::size_t offset = std::string::npos;
    std::string message = e.what();
    if (const auto* pe = dynamic_cast<const json::parse_error*>(&e)) {
      offset = pe->byte > 0 ? pe->byte - 1 : 0;
      where.clear();  // a syntax error may sit after the last key's value
    } else {
      const auto open = message.find("parsing '"), close = message.rfind('\'');
      if (open != std::string::npos && close > open + 9) {
        const std::string number = message.substr(open + 9, close - open - 9);
        offset = raw.find(number);
        if (e.id == 406)
          message = "the number " + number + " is too large for a double (at most about 1.8e308)";
      }
    }
    std::string at;
    if (offset != std::string::npos && offset <= raw.size()) {
      const auto line = 1 + std::count(raw.begin(), raw.begin() + offset, '\n');
      const auto start = raw.rfind('\n', offset == 0 ? 0 : offset - 1);
      const auto column = offset - (start == std::string::npos ? 0 : start + 1) + 1;
      at = " (line " + std::to_string(line) + ", column " + std::to_string(column) + ")";
    }
    throw SceneError(path + ": " + (where.empty() ? "" : where + ": ") + "invalid JSON" + at +
                     ": " + message);
  }
  return parse_scene(document, path);
}

std::vector<Seed> body_seeds(const Scene& scene, std::size_t body) {
  if (body >= scene.bodies.size() || scene.dimension < 1 || scene.dimension > 3)
    throw std::out_of_range("body_seeds: no such body");
  const BodySpec& b = scene.bodies[body];
  std::vector<Seed> seeds;
  for_each_seed(scene, b, box_cells(scene, b.box_min, b.box_max), [&](const Seed& seed) {
    seeds.push_back(seed);
    return true;
  });
  return seeds;
}

std::array<std::pair<int, int>, 3> box_cells(const Scene& scene, const std::vector<double>& lo,
                                             const std::vector<double>& hi) {
  std::array<std::pair<int, int>, 3> ranges{};
  for (int a = 0; a < scene.dimension; ++a) {
    const auto ax = static_cast<std::size_t>(a);
    ranges[ax] = cell_range(scene.grid, lo[ax], hi[ax], a);
  }
  return ranges;
}

}  // namespace dgmpm::scene
