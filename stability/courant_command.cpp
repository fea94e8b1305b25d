#include "stability/courant_command.hpp"

#include "stability/admissible_courant.hpp"
#include "stability/courant_map.hpp"

#include <nlohmann/json.hpp>

#include <iomanip>
#include <iostream>
#include <memory>
#include <sstream>
#include <stdexcept>

namespace dgmpm::stability {
namespace {

SceneAnalysis& scene_analysis() {
  static SceneAnalysis analysis;
  return analysis;
}

struct CourantOptions {
  std::string scene;
  std::vector<double> positions, masses;
  std::string time = "euler", criterion = "l2", model = "elastic";
  bool json = false;
  int map = 0;
};

constexpr int kInvalidInput = 2;

std::vector<double> masses_or_equal(const CellLayout& layout) {
  std::vector<double> m;
  for (int k = 0; k < layout.size(); ++k) m.push_back(layout.weight(k));
  return m;
}

void print_result(const CellLayout& layout, TimeScheme scheme, Criterion criterion, Model model,
                  const CourantResult& r, bool json, std::ostream& out) {
  if (json) {
    nlohmann::json j{{"courant", r.courant},
                     {"bounded", r.bounded},
                     {"criterion", to_string(criterion)},
                     {"time", to_string(scheme)},
                     {"model", to_string(model)},
                     {"positions", layout.positions},
                     {"masses", masses_or_equal(layout)}};
    if (r.bounded) {
      j["failing_courant"] = r.failing_courant;
      j["failing_direction"] = r.direction;
      if (criterion == Criterion::l2)
        j["critical_theta"] = r.critical_theta;
      else
        j["limiting_particle"] = r.limiting_particle;
    }
    out << j.dump() << '\n';
    return;
  }
  std::ostringstream line;
  line << std::fixed << std::setprecision(6);
  if (r.bounded)
    line << "admissible Courant number C* = " << r.courant;
  else
    line << "admissible Courant number C* >= " << r.courant << " (nothing fails up to it)";
  line << " (" << to_string(criterion) << ", " << to_string(scheme) << ", " << to_string(model)
       << "; positions " << describe(layout.positions) << "; masses "
       << describe(masses_or_equal(layout)) << ")";
  if (r.bounded) {
    if (criterion == Criterion::l2 && r.critical_theta == 0.0)
      line << "; first unstable modes: long waves (theta -> 0), wave to " << r.direction;
    else if (criterion == Criterion::l2)
      line << "; first unstable mode theta = " << std::setprecision(4) << r.critical_theta
           << " rad, wave to " << r.direction;
    else
      line << "; limiting particle " << r.limiting_particle + 1 << " (xi = " << std::defaultfloat
           << layout.positions[r.limiting_particle] << "), wave to " << r.direction;
  }
  out << line.str() << '\n';
}

void print_map(int n, const std::vector<double>& masses, TimeScheme scheme, Criterion criterion,
               Model model, std::ostream& out) {
  const std::vector<double> c = two_particle_courant_map(n, masses, scheme, criterion, model);
  out << "x1,x2,courant\n" << std::setprecision(10);
  for (int i = 0; i < n; ++i)
    for (int j = 0; j < n; ++j)
      out << (i + 0.5) / n << ',' << (j + 0.5) / n << ',' << c[i * n + j] << '\n';
}

int run(const CourantOptions& o, std::ostream& out, std::ostream& err) {
  try {
    const TimeScheme scheme = parse_time_scheme(o.time);
    const Criterion criterion = parse_criterion(o.criterion);
    const Model model = parse_model(o.model);
    if (!o.scene.empty()) {
      if (!scene_analysis()) throw std::invalid_argument("--scene is not available in this build");
      return scene_analysis()(o.scene, o.json, out, err);
    }
    if (o.map > 0) {
      print_map(o.map, o.masses, scheme, criterion, model, out);
      return 0;
    }
    if (o.positions.empty())
      throw std::invalid_argument("give the particle positions (--positions 0.25,0.75) or --map N");
    const CellLayout layout{o.positions, o.masses};
    validate(layout);
    print_result(layout, scheme, criterion, model,
                 admissible_courant(layout, scheme, criterion, model), o.json, out);
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
  auto options = std::make_shared<CourantOptions>();
  CLI::App* sub = app.add_subcommand(
      "courant",
      "Admissible Courant number C* = c dt / dx of a DGMPM particle layout: the largest C* such "
      "that every C in (0, C*] passes the criterion (von Neumann analysis of a periodic grid of "
      "identical cells, from the solver's own operators).");
  CLI::Option* positions =
      sub->add_option("--positions", options->positions,
                      "Particle positions in the cell, local coordinates in [0, 1], comma "
                      "separated (e.g. 0.25,0.75)")
          ->delimiter(',');
  sub->add_option("--masses", options->masses,
                  "Relative particle masses, one per position, comma separated (default: equal); "
                  "the cell's particles carry a full cell's mass")
      ->delimiter(',');
  sub->add_option("--time", options->time, "Time integrator: euler or rk2")
      ->check(CLI::IsMember({"euler", "rk2"}))
      ->capture_default_str();
  sub->add_option("--criterion", options->criterion,
                  "l2 (von Neumann: spectral radius of G(theta) <= 1) or monotone (sum of "
                  "|row| of the one-step particle map <= 1: no new extrema)")
      ->check(CLI::IsMember({"l2", "monotone"}))
      ->capture_default_str();
  sub->add_option("--model", options->model,
                  "elastic (1D bar, waves both ways) or advection (u_t + a u_x = 0, a > 0)")
      ->check(CLI::IsMember({"elastic", "advection"}))
      ->capture_default_str();
  CLI::Option* json = sub->add_flag("--json", options->json,
                                    "Print one JSON object (courant, criterion, time, model, "
                                    "positions, masses, critical_theta or limiting_particle)");
  sub->add_option("--map", options->map,
                  "Print C* as CSV (x1,x2,courant) over an N x N grid of two-particle layouts, "
                  "positions (i + 1/2) / N")
      ->check(CLI::Range(1, 10000))
      ->excludes(positions)
      ->excludes(json);
  sub->add_option("--scene", options->scene,
                  "Analyse a whole DGMPM scene instead: largest Courant number at which the "
                  "spectral radius of its global one-step operator (ARPACK, each product one "
                  "solver step, boundary values set to zero) stays <= 1")
      ->check(CLI::ExistingFile)
      ->excludes(positions);
  sub->callback([options, &out, &err] {
    if (const int code = run(*options, out, err); code != 0) throw CLI::RuntimeError(code);
  });
}

void add_courant_command(CLI::App& app) {
  add_courant_command(app, std::cout, std::cerr);
}

int courant_main(const std::vector<std::string>& args, std::ostream& out, std::ostream& err) {
  CLI::App app{"dgmpm"};
  app.require_subcommand(1);
  add_courant_command(app, out, err);
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
