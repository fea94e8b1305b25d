#pragma once
// A scene: everything a run needs, read from a JSON file (README.md, "Scene files").
// parse_scene validates the whole document before any step and throws SceneError whose message
// names the key path, the value found and what is allowed.

#include <dgmpm/boundary.hpp>
#include <dgmpm/dg_operator.hpp>
#include <dgmpm/discretisation.hpp>
#include <dgmpm/physics/hyperelastic_laws.hpp>
#include <dgmpm/physics/plastic_flow.hpp>
#include <stability/options.hpp>

#include <array>
#include <cstddef>
#include <nlohmann/json.hpp>
#include <optional>
#include <stdexcept>
#include <string>
#include <utility>
#include <variant>
#include <vector>

namespace dgmpm::scene {

struct SceneError : std::runtime_error {
  using std::runtime_error::runtime_error;
};

enum class Method { dgmpm, mpm_usl, mpm_usf, mpm_musl };
enum class MpmUpdate { flip, pic };
// The stability analysis' own names: a scene asks for exactly what stability/ analyses.
using Integrator = stability::TimeScheme;
using Criterion = stability::Criterion;
using stability::to_string;

struct GridSpec {
  std::vector<double> origin, cell_size;  // one entry per dimension
  std::vector<int> cells;
  std::array<bool, 3> periodic{};  // per axis; "periodic": true means every axis
  double upper(std::size_t axis) const { return origin[axis] + cells[axis] * cell_size[axis]; }
};

// The material models a scene can name ("model"), each with the keys of its own beside the
// elastic constants every model has; scene.cpp parses each with a function of its own.
struct LinearElastic {};  // "linear_elastic", the default
struct ElastoPlastic {    // "elastoplastic": J2 flow, isotropic and kinematic hardening
  PlasticFlow flow;
};
struct ElastoViscoplastic {  // "elasto_viscoplastic": Perzyna (flow.relaxation_time > 0)
  PlasticFlow flow;
};
// "saint_venant_kirchhoff", "neo_hookean" (finite strain: density is the reference density rho0)
template <class Law>
struct Hyperelastic {};
using MaterialModel = std::variant<LinearElastic, ElastoPlastic, ElastoViscoplastic,
                                   Hyperelastic<SaintVenantKirchhoff>, Hyperelastic<NeoHookean>>;

struct MaterialSpec {
  std::string name;
  MaterialModel model;
  double young = 0, poisson = 0, density = 0;
  const char* model_name() const;  // as the scene names it
  bool plastic() const {
    return std::holds_alternative<ElastoPlastic>(model) ||
           std::holds_alternative<ElastoViscoplastic>(model);
  }
  bool finite_strain() const {
    return std::holds_alternative<Hyperelastic<SaintVenantKirchhoff>>(model) ||
           std::holds_alternative<Hyperelastic<NeoHookean>>(model);
  }
  // The plastic flow of a plastic model; otherwise an infinite yield stress (elastic).
  PlasticFlow flow() const {
    if (const auto* m = std::get_if<ElastoPlastic>(&model)) return m->flow;
    if (const auto* m = std::get_if<ElastoViscoplastic>(&model)) return m->flow;
    return {};
  }
};

struct BodySpec {
  int material = 0;  // index into Scene::materials
  std::vector<double> box_min, box_max;
  // Local coordinates in [0, 1]^dimension of the particles of one cell (unused axes 0). From
  // "particles_per_cell" [N_x, N_y]: ((i + 1/2) / N_x, (j + 1/2) / N_y), x fastest.
  std::vector<std::array<double, 3>> layout;
  std::vector<double> masses_in_cell;  // relative weights, one per particle; equal by default
  std::vector<double> velocity;        // dimension entries
  std::vector<double> stress;          // 1D: [sigma]; 2D: [sigma_xx, sigma_yy, sigma_xy]
  // Finite strain: the initial deformation gradient (1D: [F_xx]); empty: unstrained.
  std::vector<double> deformation_gradient;
};

// One condition on a side, or on the segment [range_lo, range_hi] of it (2D: metres along the
// side's other axis).
struct BoundarySpec {
  BoundaryKind kind = BoundaryKind::free;
  std::vector<double> times;   // one entry for a constant value
  std::vector<double> values;  // dimension entries per time (traction: sigma_nn, sigma_nt)
  bool has_range = false;
  double range_lo = 0, range_hi = 0;
};

struct TimeSpec {
  double end = 0;
  Integrator integrator = Integrator::euler;
  bool courant_auto = false;
  double courant = 1.0;  // when not auto
  // auto only: budget (l2, or a growth within growth_budget over the run), l2 or monotone.
  Criterion criterion = Criterion::budget;
  double growth_budget = 1.01;
  // auto only: every this many steps (0: never) the whole scene's frozen operator is checked at
  // the chosen step, which is halved until its spectral radius is at most 1 (serial runs).
  long check_scene_every = 0;
  double safety = 1.0;  // auto only
  // A run stops (exit 1) when its energy exceeds blow_up_factor times (initial energy + work of
  // the loads), unless blow_up_check is false.
  bool blow_up_check = true;
  double blow_up_factor = 10.0;
  // A run needing more steps is refused up front (or stopped, when "auto" shrinks the step).
  long max_steps = 10'000'000;
};

struct OutputSpec {
  std::string directory;      // empty: nothing written
  std::vector<double> times;  // particle fields written at these times (sorted)
  bool csv = true;            // particles_NNN.csv
  bool vtu = false;           // particles_NNN.vtu and particles.pvd (default in 2D)
  bool vtu_binary = false;    // raw appended arrays (default in 2D), else ASCII
  // Steps land on output times (shortened to reach them exactly), or the step sequence is left
  // unchanged and each output is written at the step nearest its time.
  bool land = true;
};

struct Scene {
  int dimension = 1;
  Method method = Method::dgmpm;
  MpmUpdate update = MpmUpdate::flip;
  GridSpec grid;
  std::vector<MaterialSpec> materials;
  std::vector<BodySpec> bodies;
  FluxScheme flux = FluxScheme::dcu;  // DGMPM in 2D
  // [axis][side]: xmin, xmax, ymin, ...; segments sorted along the side, disjoint; none: free.
  std::vector<BoundarySpec> boundaries[3][2];
  TimeSpec time;
  bool particles_move = false;
  // 1D: a bar in uniaxial stress (modulus E), or a plane wave in uniaxial strain (modulus
  // lambda + 2 mu; sigma_yy = sigma_zz from the plastic strain).
  bool uniaxial_strain = false;
  Formulation formulation = Formulation::consistent;  // DGMPM
  std::optional<std::string> exact;                   // "bar" (1D), "plane_wave" (2D)
  // 2D: a smooth plane wave added to the bodies' initial state on a doubly periodic grid:
  // v = amplitude sin(k . x) times the polarisation (k for a P wave, k turned by +90 degrees for
  // an S wave), k = 2 pi (cycles_x / L_x, cycles_y / L_y), stress that of the travelling wave.
  struct PlaneWave {
    bool shear = false;
    std::array<int, 2> cycles{1, 0};
    double amplitude = 1.0;
  };
  std::optional<PlaneWave> plane_wave;
  OutputSpec output;
  std::string source;       // file name, for messages
  nlohmann::json document;  // the parsed file (a checkpoint records it: restarts check it)
};

Scene parse_scene(const nlohmann::json& document, const std::string& source = "scene");
Scene load_scene(const std::string& path);  // SceneError also for unreadable or invalid JSON
// A scene file's text (duplicate keys refused, JSON errors with line and column); `source` names
// it in messages.
Scene parse_scene_text(const std::string& text, const std::string& source);

const char* to_string(Method);
const char* to_string(MpmUpdate);

// One particle a body generates. Its position on each axis is exactly
// origin + (cell + layout[local]) * cell_size, evaluated in that order, and the body's box claims
// it when box_min <= x < box_max on every axis. Validation uses the same rule, so a parsed
// scene's bodies each hold at least one seed and no seed lies in two boxes.
struct Seed {
  std::array<int, 3> cell{};  // per axis; unused axes 0
  int local = 0;              // index into layout and masses_in_cell
  std::array<double, 3> x{};  // per axis; unused axes 0
};

// Per axis, the range [first, last] of grid cells whose particles may lie in [lo, hi) (one cell
// of margin against rounding, clamped to the grid).
std::array<std::pair<int, int>, 3> box_cells(const Scene& scene, const std::vector<double>& lo,
                                             const std::vector<double>& hi);
// The seeds of scene.bodies[body]: cell by cell (the first axis fastest) and, inside a cell, in
// the order of the layout.
std::vector<Seed> body_seeds(const Scene& scene, std::size_t body);

}  // namespace dgmpm::scene
