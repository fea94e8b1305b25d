#include "stability/courant_command.hpp"

#include "stability/admissible_courant.hpp"
#include "stability/courant_map.hpp"

#include <nlohmann/json.hpp>

#include <cstdlib>
#include <initializer_list>
#include <iomanip>
#include <iostream>
#include <memory>
#include <optional>
#include <sstream>
#include <stdexcept>
#include <utility>

namespace dgmpm::stability {
namespace {

SceneAnalysis& scene_analysis() {
  static SceneAnalysis analysis;
  return analysis;
}

struct CourantOptions {
  std::string scene;
  std::string positions, masses;  // comma separated, split here: empty entries are refused
  std::vector<double> speeds;
  std::string time = "euler", criterion = "l2", model = "elastic", flux = "dcu";
  std::string formulation = "consistent";
  int dim = 1;
  double poisson = 0.3, aspect = 1.0;
  double budget = 1.1, steps = 0;  // the growth budget: steps > 0 asks for it
  bool json = false;
  int map = 0;
  CourantAnalysis analysis = CourantAnalysis::all;
  // The options the user gave (CLI11 counts), to refuse those that do not apply.
  std::vector<std::pair<std::string, const CLI::Option*>> given;
  bool has(const std::string& name) const {
    for (const auto& [n, o] : given)
      if (n == name) return o->count() > 0;
    return false;
  }
};

constexpr int kInvalidInput = 2;

std::vector<double> masses_or_equal(const CellLayout& layout) {
  std::vector<double> m;
  for (int k = 0; k < layout.size(); ++k) m.push_back(layout.weight(k));
  return m;
}

// Comma-separated entries, empty ones kept (and refused by their parsers).
std::vector<std::string> split(const std::string& text) {
  std::vector<std::string> parts;
  std::size_t start = 0;
  while (true) {
    const std::size_t end = text.find(',', start);
    parts.push_back(text.substr(start, end == std::string::npos ? end : end - start));
    if (end == std::string::npos) return parts;
    start = end + 1;
  }
}

std::vector<double> parse_masses(const std::string& text) {
  std::vector<double> masses;
  if (text.empty()) return masses;
  const auto parts = split(text);
  for (std::size_t k = 0; k < parts.size(); ++k) {
    char* stop = nullptr;
    const double m = std::strtod(parts[k].c_str(), &stop);
    if (parts[k].empty() || stop != parts[k].c_str() + parts[k].size())
      throw std::invalid_argument("--masses: entry " + std::to_string(k + 1) + " ('" + parts[k] +
                                  "') is not a number");
    masses.push_back(m);
  }
  return masses;
}

// "0.25" (1D) or "0.25:0.5" (2D), all of it a number per coordinate.
std::vector<double> parse_position(const std::string& entry, int index, int dim) {
  const std::string where = "--positions: entry " + std::to_string(index + 1);
  if (entry.empty())
    throw std::invalid_argument(where + " is empty; give " + std::to_string(dim) +
                                (dim == 1 ? " number" : " numbers separated by ':'") +
                                " per particle");
  std::vector<double> x;
  std::size_t start = 0;
  while (true) {
    const std::size_t end = entry.find(':', start);
    const std::string part = entry.substr(start, end == std::string::npos ? end : end - start);
    char* stop = nullptr;
    const double v = part.empty() ? 0.0 : std::strtod(part.c_str(), &stop);
    if (part.empty() || stop != part.c_str() + part.size())
      throw std::invalid_argument(where + " ('" + entry + "') is not " +
                                  (dim == 1 ? "a number" : "x:y with two numbers"));
    x.push_back(v);
    if (end == std::string::npos) break;
    start = end + 1;
  }
  if (static_cast<int>(x.size()) != dim)
    throw std::invalid_argument(where + " ('" + entry + "') has " + std::to_string(x.size()) +
                                " coordinates; --dim " + std::to_string(dim) + " needs " +
                                std::to_string(dim) + (dim == 2 ? " (x:y)" : ""));
  return x;
}

std::string setting_text(const AnalysisSetting& s) {
  std::ostringstream t;
  t << to_string(s.time) << ", " << to_string(s.model);
  if (s.dim > 1) {
    if (s.model == Model::elastic)
      t << " nu " << s.poisson;
    else
      t << " speeds " << s.speed_x << ", " << s.speed_y;
    t << ", " << to_string(s.flux) << ", aspect " << s.aspect;
  }
  return t.str();
}

// The 2D setting's keys of a JSON answer (flux, aspect, and poisson or speeds).
void add_2d_setting(nlohmann::json& j, const AnalysisSetting& setting) {
  j["flux"] = to_string(setting.flux);
  j["aspect"] = setting.aspect;
  if (setting.model == Model::elastic)
    j["poisson"] = setting.poisson;
  else
    j["speeds"] = {setting.speed_x, setting.speed_y};
}

void print_result(const CellLayout& layout, const AnalysisSetting& setting, Criterion criterion,
                  const CourantResult& r, const std::optional<BudgetedCourant>& b,
                  const GrowthBudget& budget, bool json, std::ostream& out) {
  if (json) {
    nlohmann::json positions = nlohmann::json::array();
    for (int k = 0; k < layout.size(); ++k) {
      if (layout.dim == 1) {
        positions.push_back(layout.position(k, 0));
      } else {
        positions.push_back({layout.position(k, 0), layout.position(k, 1)});
      }
    }
    nlohmann::json j{{"courant", r.courant},
                     {"bounded", r.bounded},
                     {"criterion", to_string(criterion)},
                     {"time", to_string(setting.time)},
                     {"model", to_string(setting.model)},
                     {"dim", setting.dim},
                     {"positions", positions},
                     {"masses", masses_or_equal(layout)}};
    if (setting.dim > 1) add_2d_setting(j, setting);
    if (r.bounded) {
      j["failing_courant"] = r.failing_courant;
      j["failing_direction"] = r.direction;
      if (criterion == Criterion::l2) {
        j["critical_theta"] = r.critical_theta;
        if (setting.dim > 1) j["critical_theta_y"] = r.critical_theta_y;
      } else {
        j["limiting_particle"] = r.limiting_particle;
      }
    }
    if (b)
      j["budgeted"] = {{"courant", b->courant},   {"factor", budget.factor},
                       {"steps", budget.horizon}, {"growth_per_step", b->growth},
                       {"bounded", b->bounded},   {"weakly_unstable", b->extended}};
    out << j.dump() << '\n';
    return;
  }
  std::ostringstream line;
  line << std::fixed << std::setprecision(6);
  if (r.bounded)
    line << "admissible Courant number C* = " << r.courant;
  else
    line << "admissible Courant number C* >= " << r.courant << " (nothing fails up to it)";
  line << " (" << to_string(criterion) << ", " << setting_text(setting) << "; positions "
       << describe_positions(layout) << "; masses " << describe(masses_or_equal(layout)) << ")";
  if (r.bounded) {
    if (criterion == Criterion::l2 && setting.dim > 1)
      line << "; first unstable mode theta = (" << std::setprecision(4) << r.critical_theta << ", "
           << r.critical_theta_y << ") rad";
    else if (criterion == Criterion::l2 && r.critical_theta == 0.0)
      line << "; first unstable modes: long waves (theta -> 0), wave to " << r.direction;
    else if (criterion == Criterion::l2)
      line << "; first unstable mode theta = " << std::setprecision(4) << r.critical_theta
           << " rad, wave to " << r.direction;
    else
      line << "; limiting particle " << r.limiting_particle
           << " (numbered from 0; x = " << std::defaultfloat
           << describe_positions(
                  CellLayout{std::vector<double>(
                                 layout.positions.begin() + r.limiting_particle * layout.dim,
                                 layout.positions.begin() + (r.limiting_particle + 1) * layout.dim),
                             {},
                             layout.dim})
           << "), wave to " << r.direction;
  }
  out << line.str() << '\n';
  if (b) {
    std::ostringstream more;
    more << std::fixed << std::setprecision(6)
         << "budgeted Courant number C = " << (b->bounded ? "" : ">= ") << b->courant
         << " (no mode grows by more than " << std::defaultfloat << budget.factor << " over "
         << budget.horizon << " steps: "
         << "growth per step at most " << budget.allowance(b->courant) << "; "
         << (b->extended ? "weakly unstable above C*, growth " : "C* kept, growth ") << b->growth
         << " per step there)";
    out << more.str() << '\n';
  }
}

// A map as CSV (a first line saying what was analysed, then a header) or as one JSON object:
// the setting's keys, "columns" and "map" (one [coordinates..., C*] row per layout).
void write_map(std::ostream& out, bool json, const AnalysisSetting& setting, Criterion criterion,
               const std::vector<double>& masses, const std::vector<std::string>& columns,
               const std::vector<std::vector<double>>& rows) {
  if (json) {
    nlohmann::json j{{"criterion", to_string(criterion)},
                     {"time", to_string(setting.time)},
                     {"model", to_string(setting.model)},
                     {"dim", setting.dim},
                     {"columns", columns},
                     {"map", rows}};
    if (setting.dim == 1)
      j["masses"] = masses.empty() ? std::vector<double>{1.0, 1.0} : masses;
    else
      add_2d_setting(j, setting);
    out << j.dump() << '\n';
    return;
  }
  out << "# C* of " << (setting.dim == 1 ? "two particles" : "one particle per cell") << " at ("
      << columns[0];
  for (std::size_t k = 1; k + 1 < columns.size(); ++k) out << ", " << columns[k];
  out << "): " << to_string(criterion) << ", " << setting_text(setting);
  if (setting.dim == 1)
    out << ", masses " << describe(masses.empty() ? std::vector<double>{1.0, 1.0} : masses);
  out << '\n';
  for (std::size_t k = 0; k < columns.size(); ++k) out << (k ? "," : "") << columns[k];
  out << '\n' << std::setprecision(10);
  for (const auto& row : rows)
    for (std::size_t k = 0; k < row.size(); ++k) out << row[k] << (k + 1 < row.size() ? ',' : '\n');
}

// 1D: C* of two particles at ((i + 1/2) / n, (j + 1/2) / n).
void print_map(int n, const std::vector<double>& masses, const AnalysisSetting& setting,
               Criterion criterion, bool json, std::ostream& out) {
  const std::vector<double> c =
      two_particle_courant_map(n, masses, setting.time, criterion, setting.model);
  std::vector<std::vector<double>> rows;
  for (int i = 0; i < n; ++i)
    for (int j = 0; j < n; ++j) rows.push_back({(i + 0.5) / n, (j + 0.5) / n, c[i * n + j]});
  write_map(out, json, setting, criterion, masses, {"x1", "x2", "courant"}, rows);
}

// 2D: C* of one particle at ((i + 1/2) / n, (j + 1/2) / n).
void print_map_2d(int n, const AnalysisSetting& setting, Criterion criterion, bool json,
                  std::ostream& out) {
  std::vector<std::vector<double>> rows;
  for (int j = 0; j < n; ++j)
    for (int i = 0; i < n; ++i) {
      const double x = (i + 0.5) / n, y = (j + 0.5) / n;
      rows.push_back(
          {x, y, admissible_courant(CellLayout{{x, y}, {}, 2}, setting, criterion).courant});
    }
  write_map(out, json, setting, criterion, {}, {"x", "y", "courant"}, rows);
}

// Refuses the options given that do not apply (names listed), saying why.
void refuse_given(const CourantOptions& o, std::initializer_list<const char*> names,
                  const std::string& why) {
  for (const char* name : names)
    if (o.has(name)) throw std::invalid_argument(std::string(name) + " does not apply " + why);
}

int run(const CourantOptions& o, std::ostream& out, std::ostream& err) {
  try {
    if (!o.scene.empty()) {
      refuse_given(o,
                   {"--positions", "--masses", "--time", "--criterion", "--model", "--map", "--dim",
                    "--flux", "--speeds", "--poisson", "--aspect", "--formulation", "--budget",
                    "--steps"},
                   "to --scene: the scene's own particles, integrator, flux and materials are "
                   "analysed (L2 criterion)");
      if (!scene_analysis()) throw std::invalid_argument("--scene is not available in this build");
      if (o.analysis != CourantAnalysis::all) return 0;
      return scene_analysis()(o.scene, o.json, out, err);
    }
    AnalysisSetting setting;
    setting.dim = o.dim;
    setting.time = parse_time_scheme(o.time);
    setting.model = parse_model(o.model);
    setting.formulation = o.formulation == "paper" ? Formulation::paper : Formulation::consistent;
    const Criterion criterion = parse_criterion(o.criterion);
    if (o.dim == 1) {
      refuse_given(o, {"--flux", "--speeds", "--poisson", "--aspect"},
                   "in 1D (--dim 2 for 2D analyses)");
    } else {
      setting.flux = o.flux == "ctu" ? FluxScheme::ctu : FluxScheme::dcu;
      setting.aspect = o.aspect;
      if (setting.model == Model::elastic) {
        refuse_given(o, {"--speeds"}, "to --model elastic (waves at c_p and c_s)");
        if (!(o.poisson > -1 && o.poisson < 0.5))
          throw std::invalid_argument("--poisson " + std::to_string(o.poisson) +
                                      " is outside (-1, 0.5)");
        setting.poisson = o.poisson;
      } else {
        refuse_given(o, {"--poisson"}, "to --model advection");
        if (o.has("--speeds")) {
          if (o.speeds.size() != 2 || !(o.speeds[0] >= 0 && o.speeds[1] >= 0) ||
              !(o.speeds[0] + o.speeds[1] > 0))
            throw std::invalid_argument(
                "--speeds takes two speeds a,b >= 0, not both 0 (u_t + a u_x + b u_y = 0)");
          setting.speed_x = o.speeds[0];
          setting.speed_y = o.speeds[1];
        } else {
          setting.speed_y = 1.0;  // a = b = 1
        }
      }
    }
    const std::vector<double> masses = parse_masses(o.masses);
    if (o.has("--masses") && masses.empty())
      throw std::invalid_argument("--masses is empty; give one mass per particle, or no --masses");
    if (o.map > 0) {
      if (o.analysis != CourantAnalysis::all) return 0;
      if (o.dim == 1) {
        print_map(o.map, masses, setting, criterion, o.json, out);
      } else {
        refuse_given(o, {"--masses"}, "to a 2D --map (one particle per cell)");
        print_map_2d(o.map, setting, criterion, o.json, out);
      }
      return 0;
    }
    if (!o.has("--positions"))
      throw std::invalid_argument(
          "give the particle positions (--positions 0.25,0.75; in 2D 0.25:0.5,0.75:0.5) or --map "
          "N");
    CellLayout layout;
    layout.dim = o.dim;
    const auto entries = split(o.positions);
    for (std::size_t k = 0; k < entries.size(); ++k)
      for (double x : parse_position(entries[k], static_cast<int>(k), o.dim))
        layout.positions.push_back(x);
    layout.masses = masses;
    validate(layout);
    if (o.analysis == CourantAnalysis::none || (o.analysis == CourantAnalysis::quick && o.dim > 1))
      return 0;
    GrowthBudget budget;
    std::optional<BudgetedCourant> budgeted;
    if (o.has("--budget") && !o.has("--steps"))
      throw std::invalid_argument("--budget needs --steps N (the run's number of steps)");
    const OneStepMap map = build_one_step_map(layout, setting);
    if (criterion == Criterion::monotone && setting.dim > 1 && setting.model == Model::elastic)
      throw std::invalid_argument(
          "the monotone criterion needs scalar waves: the 2D elastic system does not split into "
          "them (use --criterion l2, or --model advection)");
    const CourantResult r = admissible_courant(map, criterion, default_search_options(criterion));
    if (o.has("--steps")) {
      if (criterion != Criterion::l2)
        throw std::invalid_argument("--steps asks for the growth budget, an L2 criterion");
      if (!(o.steps >= 1 && o.budget > 1))
        throw std::invalid_argument("--steps takes a number >= 1 and --budget a factor > 1");
      budget.factor = o.budget;
      budget.horizon = o.steps;
      budgeted = budgeted_courant(map, r, budget);
    }
    print_result(layout, setting, criterion, r, budgeted, budget, o.json, out);
    return 0;
  } catch (const std::exception& e) {
    err << "dgmpm courant: error: " << e.what() << '\n';
    return kInvalidInput;
  }
}

}  // namespace

void set_scene_analysis(SceneAnalysis analysis) {
  scene_analysis() = std::move(analysis);
}

void add_courant_command(CLI::App& app, std::ostream& out, std::ostream& err) {
  add_courant_command(app, out, err, CourantAnalysis::all);
}

void add_courant_command(CLI::App& app, std::ostream& out, std::ostream& err,
                         CourantAnalysis analysis) {
  auto options = std::make_shared<CourantOptions>();
  options->analysis = analysis;
  CLI::App* sub = app.add_subcommand(
      "courant",
      "Admissible Courant number C* of a DGMPM particle layout: the largest C* such that every "
      "C in (0, C*] passes the criterion (von Neumann analysis of a periodic grid of identical "
      "cells, from the solver's own operators), in 1D or 2D; or of a whole scene (--scene).");
  const auto keep = [&](CLI::Option* o) {
    options->given.emplace_back(o->get_name(), o);
    return o;
  };
  CLI::Option* positions =
      keep(sub->add_option("--positions", options->positions,
                           "Particle positions in the cell, local coordinates in [0, 1], comma "
                           "separated: 0.25,0.75 (1D), 0.25:0.5,0.75:0.5 (2D, x:y)"));
  keep(sub->add_option("--masses", options->masses,
                       "Relative particle masses, one per position, comma separated (default: "
                       "equal); the cell's particles carry a full cell's mass"));
  keep(sub->add_option("--dim", options->dim, "Dimension: 1 or 2")
           ->check(CLI::IsMember({1, 2}))
           ->capture_default_str());
  std::vector<std::string> scheme_names;
  for (TimeScheme s : time_schemes) scheme_names.push_back(to_string(s));
  keep(sub->add_option("--time", options->time, "Time integrator: euler or rk2")
           ->check(CLI::IsMember(scheme_names))
           ->capture_default_str());
  keep(sub->add_option("--flux", options->flux, "2D edge fluxes: dcu or ctu")
           ->check(CLI::IsMember({"dcu", "ctu"}))
           ->capture_default_str());
  keep(sub->add_option("--formulation", options->formulation,
                       "The scheme: consistent (constant states preserved in every cell, RK2's "
                       "near-empty nodes damped) or paper (the founding paper's form); they differ "
                       "for 2D layouts whose mass is not centred along an axis and, with RK2, for "
                       "nodes holding less than a fifth of their cell's mass")
           ->check(CLI::IsMember({"consistent", "paper"}))
           ->capture_default_str());
  keep(sub->add_option("--criterion", options->criterion,
                       "l2 (von Neumann: spectral radius of G(theta) <= 1) or monotone (sum of "
                       "|row| of the one-step particle map <= 1: no new extrema; scalar waves "
                       "only: 1D, or 2D advection)")
           ->check(CLI::IsMember({"l2", "monotone"}))
           ->capture_default_str());
  keep(sub->add_option("--steps", options->steps,
                       "Also the growth-budgeted Courant number for a run of this many steps: the "
                       "largest C at which no mode grows by more than --budget over them (the "
                       "strict L2 value where the limit is an instability's onset)"));
  keep(sub->add_option("--budget", options->budget,
                       "With --steps: the most a mode may grow over the run (a factor > 1)")
           ->capture_default_str());
  keep(sub->add_option("--model", options->model,
                       "elastic (1D bar; 2D plane strain, C = c_p dt / min(dx, dy)) or advection "
                       "(1D u_t + u_x = 0; 2D u_t + a u_x + b u_y = 0, C = dt max(a/dx, b/dy))")
           ->check(CLI::IsMember({"elastic", "advection"}))
           ->capture_default_str());
  keep(sub->add_option("--speeds", options->speeds, "2D advection speeds a,b >= 0 (default 1,1)")
           ->delimiter(','));
  keep(sub->add_option("--poisson", options->poisson, "2D elastic: Poisson's ratio")
           ->capture_default_str());
  keep(sub->add_option("--aspect", options->aspect, "2D: cell aspect ratio dx / dy")
           ->check(CLI::PositiveNumber)
           ->capture_default_str());
  CLI::Option* json = sub->add_flag(
      "--json", options->json,
      "Print one JSON object (courant, bounded, criterion, time, model, dim, positions, masses, "
      "and in 2D flux, aspect, poisson or speeds; critical_theta (and critical_theta_y) or "
      "limiting_particle); with a 2D --map, the map");
  keep(sub->add_option("--map", options->map,
                       "1D: C* as CSV (x1,x2,courant) over an N x N grid of two-particle "
                       "layouts; 2D: C* of one particle per cell over an N x N grid of its "
                       "positions (x,y,courant), positions (i + 1/2) / N")
           ->check(CLI::Range(1, 10000))
           ->excludes(positions));
  (void)json;
  sub->add_option("--scene", options->scene,
                  "Analyse a whole DGMPM scene instead (1D or 2D): largest Courant number at "
                  "which the spectral radius of its global one-step operator (ARPACK, each "
                  "product one solver step, boundary values set to zero) stays <= 1")
      ->check(CLI::ExistingFile);
  sub->callback([options, &out, &err] {
    if (const int code = run(*options, out, err); code != 0) throw CLI::RuntimeError(code);
  });
}

void add_courant_command(CLI::App& app) {
  add_courant_command(app, std::cout, std::cerr);
}

int courant_main(const std::vector<std::string>& args, std::ostream& out, std::ostream& err,
                 CourantAnalysis analysis) {
  CLI::App app{"dgmpm"};
  app.require_subcommand(1);
  add_courant_command(app, out, err, analysis);
  std::vector<std::string> reversed(args.rbegin(), args.rend());
  reversed.push_back("courant");  // CLI11 takes the arguments last first
  try {
    app.parse(reversed);
  } catch (const CLI::ParseError& e) {
    return app.exit(e, out, err);
  }
  return 0;
}

}  // namespace dgmpm::stability
