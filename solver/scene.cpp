#include "solver/scene.hpp"

#include <nlohmann/json.hpp>

#include <algorithm>
#include <cerrno>
#include <climits>
#include <cmath>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <initializer_list>
#include <iterator>
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
  return parent.empty() ? key : parent + "." + key;
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

struct AxisSeed {
  int cell, local;
  double x;
};

// The points a body claims along one axis: origin + (k + xi) h in [min, max).
std::vector<AxisSeed> axis_seeds(const GridSpec& grid, const BodySpec& body, int axis) {
  const auto a = static_cast<std::size_t>(axis);
  const double origin = grid.origin[a], h = grid.cell_size[a];
  const double lo = body.box_min[a], hi = body.box_max[a];
  const int cells = grid.cells[a];
  // Only the cells that can reach the box (one cell of margin against rounding).
  const double first = std::clamp(std::floor((lo - origin) / h) - 1, 0.0, cells - 1.0);
  const double last = std::clamp(std::ceil((hi - origin) / h) + 1, 0.0, cells - 1.0);
  std::vector<AxisSeed> seeds;
  for (int k = static_cast<int>(first); k <= static_cast<int>(last); ++k) {
    for (std::size_t j = 0; j < body.positions_in_cell.size(); ++j) {
      const double x = origin + (static_cast<double>(k) + body.positions_in_cell[j]) * h;
      if (lo <= x && x < hi) seeds.push_back({k, static_cast<int>(j), x});
    }
  }
  return seeds;
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
                  "time", "particles_move", "fill_correction", "exact", "output"});
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
    if (const json* f = find(doc, "fill_correction")) {
      s.fill_correction = boolean(*f, "fill_correction");
      if (s.fill_correction && s.method != Method::dgmpm)
        refuse("fill_correction", *f, "is a DGMPM option", "false with MPM methods");
    }
    if (const json* e = find(doc, "exact")) {
      choice<int>(*e, "exact", {{"bar", 0}});
      s.exact = "bar";
    }
    s.output.times = {s.time.end};
    if (const json* o = find(doc, "output")) parse_output(*o, s);
    return s;
  }

 private:
  std::string source_;

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
    std::vector<std::string> names(keys.begin(), keys.end());
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
    if (v.is_number() && (v.get<double>() == 2 || v.get<double>() == 3))
      refuse("dimension", v,
             "is not allowed: " + std::to_string(v.get<int>()) + "D is not implemented yet", "1");
    return integer(v, "dimension", 1, 1, "1 (2D and 3D are not implemented yet)");
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
    if (const json* p = find(g, "periodic")) grid.periodic = boolean(*p, "grid.periodic");
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
      check_object(v, path, {"model", "young", "poisson", "density"});
      MaterialSpec mat;
      mat.name = it.key();
      if (const json* model = find(v, "model")) {
        choice<int>(*model, key_path(path, "model"), {{"linear_elastic", 0}});
        mat.model = "linear_elastic";
      }
      mat.young = positive(require(v, path, "young", "a number > 0"), key_path(path, "young"));
      mat.density =
          positive(require(v, path, "density", "a number > 0"), key_path(path, "density"));
      if (const json* nu = find(v, "poisson")) {
        const std::string allowed = "-1 < poisson < 0.5";
        mat.poisson = number(*nu, key_path(path, "poisson"), allowed);
        if (!(mat.poisson > -1 && mat.poisson < 0.5))
          not_allowed(key_path(path, "poisson"), *nu, allowed);
      }
      out.push_back(mat);
    }
    return out;
  }

  TimeSpec parse_time(const json& t) const {
    check_object(t, "time", {"end", "integrator", "courant", "criterion", "safety"});
    TimeSpec time;
    time.end = positive(require(t, "time", "end", "a number > 0"), "time.end");
    if (const json* i = find(t, "integrator"))
      time.integrator = named(*i, "time.integrator", {Integrator::euler, Integrator::rk2});
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
      time.criterion = named(*c, "time.criterion", {Criterion::l2, Criterion::monotone});
    }
    if (const json* s = find(t, "safety")) {
      if (!time.courant_auto)
        refuse("time.safety", *s, "is not allowed without \"courant\": \"auto\"", only_auto);
      const std::string allowed = "0 < safety <= 1";
      time.safety = number(*s, "time.safety", allowed);
      if (!(time.safety > 0 && time.safety <= 1)) not_allowed("time.safety", *s, allowed);
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
                  "velocity", "stress"});
    BodySpec body;
    const auto n = static_cast<std::size_t>(s.dimension);
    const std::string per_axis = "one per axis, dimension " + std::to_string(s.dimension);

    std::vector<std::string> names;
    for (const auto& m : s.materials) names.push_back(m.name);
    const std::string material_path = key_path(path, "material");
    const json& m = require(b, path, "material", "one of " + join(names));
    if (!m.is_string()) wrong_type(material_path, m, "one of " + join(names));
    const auto it = std::find(names.begin(), names.end(), m.get<std::string>());
    if (it == names.end())
      refuse(material_path, m, "is not a material of this scene", "one of " + join(names));
    body.material = static_cast<int>(it - names.begin());

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
      const int count = integer(*ppc, ppc_path, 1, max_particles_per_cell);
      for (int k = 0; k < count; ++k) body.positions_in_cell.push_back((k + 0.5) / count);
    } else {
      const std::string allowed =
          "an array of 1 to " + std::to_string(max_particles_per_cell) + " numbers in [0, 1]";
      array(*pic, pic_path, allowed);
      if (pic->empty() || pic->size() > max_particles_per_cell)
        refuse(pic_path, *pic, "has " + std::to_string(pic->size()) + " entries", allowed);
      for (std::size_t j = 0; j < pic->size(); ++j) {
        const std::string p = index_path(pic_path, j);
        const double xi = number((*pic)[j], p, "a number in [0, 1]");
        if (!(xi >= 0 && xi <= 1)) not_allowed(p, (*pic)[j], "a number in [0, 1]");
        body.positions_in_cell.push_back(xi);
      }
    }
    const std::size_t layout = body.positions_in_cell.size();
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
    return body;
  }

  // Every body holds a particle; no particle lies in two boxes.
  void check_seeds(const Scene& s, const json& bodies) const {
    const auto nb = s.bodies.size();
    std::vector<std::vector<std::vector<AxisSeed>>> seeds(nb);  // [body][axis]
    for (std::size_t i = 0; i < nb; ++i) {
      for (int a = 0; a < s.dimension; ++a) {
        seeds[i].push_back(axis_seeds(s.grid, s.bodies[i], a));
        if (seeds[i].back().empty())
          refuse(index_path("bodies", i) + ".box", bodies[i]["box"],
                 "holds no particle: no origin + (k + xi) * cell_size with xi in " +
                     numbers_text(s.bodies[i].positions_in_cell) + " lies in [min, max) on axis " +
                     axis_names[a],
                 "a box holding at least one particle");
      }
    }
    for (std::size_t j = 0; j < nb; ++j) {
      for (std::size_t i = 0; i < j; ++i) {
        // A seed of body p inside body q's box, found axis by axis since both are products.
        for (const auto& [p, q] : {std::pair{i, j}, std::pair{j, i}}) {
          std::vector<double> x;
          std::vector<int> cell;
          for (int a = 0; a < s.dimension; ++a) {
            const auto ax = static_cast<std::size_t>(a);
            const auto& lo = s.bodies[q].box_min[ax];
            const auto& hi = s.bodies[q].box_max[ax];
            for (const auto& seed : seeds[p][ax]) {
              if (lo <= seed.x && seed.x < hi) {
                x.push_back(seed.x);
                cell.push_back(seed.cell);
                break;
              }
            }
          }
          if (x.size() != static_cast<std::size_t>(s.dimension)) continue;
          std::string cell_text;
          for (std::size_t a = 0; a < cell.size(); ++a)
            cell_text += (a ? ", " : "") + std::to_string(cell[a]);
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
      if (s.grid.periodic)
        refuse(path, it.value(), "is not allowed on a periodic grid",
               "no boundaries entry when grid.periodic is true");
      s.boundaries[index / 2][index % 2] = parse_boundary(it.value(), path);
    }
  }

  BoundarySpec parse_boundary(const json& v, const std::string& path) const {
    check_object(v, path, {"type", "value"});
    BoundarySpec bc;
    const std::string type_path = key_path(path, "type");
    bc.kind = named(
        require(v, path, "type", "one of free, fixed, traction, velocity"), type_path,
        {BoundaryKind::free, BoundaryKind::fixed, BoundaryKind::traction, BoundaryKind::velocity});
    const std::string value_path = key_path(path, "value");
    const std::string allowed = "a number or a table [[t0, v0], [t1, v1], ...]";
    const json* value = find(v, "value");
    const bool needs_value = bc.kind == BoundaryKind::traction || bc.kind == BoundaryKind::velocity;
    if (!needs_value) {
      if (value)
        refuse(value_path, *value,
               std::string("is not allowed with type \"") + dgmpm::to_string(bc.kind) + "\"",
               "no value for free and fixed ends");
      return bc;
    }
    if (!value)
      fail(value_path, std::string("missing required key for type \"") + dgmpm::to_string(bc.kind) +
                           "\"; allowed: " + allowed);
    if (value->is_number()) {
      bc.times = {0.0};
      bc.values = {number(*value, value_path, allowed)};
      return bc;
    }
    if (!value->is_array()) wrong_type(value_path, *value, allowed);
    if (value->empty()) refuse(value_path, *value, "is an empty table", allowed);
    for (std::size_t k = 0; k < value->size(); ++k) {
      const std::string row = index_path(value_path, k);
      const auto pair = numbers((*value)[k], row, 2, "a pair [time, value]");
      if (k == 0 && !(pair[0] >= 0))
        refuse(row + "[0]", (*value)[k][0], "is a negative time", "times >= 0");
      if (k > 0 && !(pair[0] > bc.times.back()))
        refuse(row + "[0]", (*value)[k][0],
               "is not after the previous time " + format_number(bc.times.back()),
               "strictly increasing times");
      bc.times.push_back(pair[0]);
      bc.values.push_back(pair[1]);
    }
    return bc;
  }

  void parse_output(const json& o, Scene& s) const {
    check_object(o, "output", {"directory", "times"});
    if (const json* d = find(o, "directory")) {
      if (!d->is_string()) wrong_type("output.directory", *d, "a non-empty path");
      if (d->get<std::string>().empty()) not_allowed("output.directory", *d, "a non-empty path");
      s.output.directory = d->get<std::string>();
    }
    if (const json* t = find(o, "times")) {
      const std::string allowed = "times t with 0 < t <= time.end = " + format_number(s.time.end);
      array(*t, "output.times", "an array of " + allowed);
      std::vector<double> times;
      for (std::size_t k = 0; k < t->size(); ++k) {
        const std::string p = index_path("output.times", k);
        const double x = number((*t)[k], p, allowed);
        if (!(x > 0 && x <= s.time.end)) not_allowed(p, (*t)[k], allowed);
        if (std::find(times.begin(), times.end(), x) != times.end())
          refuse(p, (*t)[k], "is listed twice", "distinct times");
        times.push_back(x);
      }
      std::sort(times.begin(), times.end());
      s.output.times = times;
    }
  }
};

}  // namespace

Scene parse_scene(const nlohmann::json& document, const std::string& source) {
  return Parser(source).parse(document);
}

Scene load_scene(const std::string& path) {
  std::error_code ec;
  if (std::filesystem::is_directory(path, ec))
    throw SceneError(path + ": cannot read the scene: it is a directory");
  std::ifstream in(path, std::ios::binary);
  if (!in) throw SceneError(path + ": cannot read the scene: " + std::strerror(errno));
  std::ostringstream text;
  text << in.rdbuf();
  if (in.bad()) throw SceneError(path + ": cannot read the scene: read error");

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
    document = json::parse(text.str(), on_event);
  } catch (const json::exception& e) {
    throw SceneError(path + ": invalid JSON: " + e.what());
  }
  return parse_scene(document, path);
}

std::vector<Seed> body_seeds(const Scene& scene, std::size_t body) {
  if (body >= scene.bodies.size() || scene.dimension < 1 || scene.dimension > 3)
    throw std::out_of_range("body_seeds: no such body");
  const BodySpec& b = scene.bodies[body];
  std::vector<std::vector<AxisSeed>> axes;
  std::size_t total = 1;
  for (int a = 0; a < scene.dimension; ++a) {
    axes.push_back(axis_seeds(scene.grid, b, a));
    total *= axes.back().size();
  }
  std::vector<Seed> seeds(total);
  for (std::size_t n = 0; n < total; ++n) {
    std::size_t rest = n;
    for (std::size_t a = 0; a < axes.size(); ++a) {
      const AxisSeed& s = axes[a][rest % axes[a].size()];
      rest /= axes[a].size();
      seeds[n].cell[a] = s.cell;
      seeds[n].local[a] = s.local;
      seeds[n].x[a] = s.x;
    }
  }
  return seeds;
}

}  // namespace dgmpm::scene
