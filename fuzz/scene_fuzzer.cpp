// libFuzzer target: a scene file's text through the parser and, when it is valid and small,
// through the set-up and a few steps of the run. Expected failures are exceptions with a message
// (refusals, blow-ups, particles leaving the grid); a crash, a sanitizer report, a hang or an
// exception of no std::exception type is a finding.
#include "solver/problem.hpp"
#include "solver/scene.hpp"
#include "solver/simulation.hpp"

#include <dgmpm/stepper.hpp>

#include <cmath>
#include <cstddef>
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <exception>
#include <string>

namespace {

using namespace dgmpm;

// How far the inputs got, printed at exit: the run script checks that the fuzzer reaches past
// validation, not only the refusals.
struct Reach {
  long inputs = 0, valid = 0, stepped = 0;
  ~Reach() {
    std::fprintf(stderr, "fuzz_scene reach: %ld inputs, %ld valid scenes, %ld stepped\n", inputs,
                 valid, stepped);
  }
} reach;

// Small enough to step within the fuzzer's time budget.
bool small_enough(const scene::Scene& s) {
  double cells = 1;
  for (int c : s.grid.cells) cells *= c;
  double seeds = 0;
  for (const auto& b : s.bodies) seeds += cells * static_cast<double>(b.layout.size());
  return cells <= 4000 && seeds <= 8000;
}

void run_a_few_steps(const scene::Scene& s) {
  with_physics(s, [&](auto physics) {
    using Physics = typename decltype(physics)::type;
    if (Physics::dim > 1 && s.method == scene::Method::dgmpm) {
      // The 2D stability analysis (the automatic step, the check of a fixed Courant number) takes
      // seconds per layout: lib's operators are stepped directly, at the scene's Courant number.
      Problem<Physics> problem = make_problem<Physics>(s);
      Stepper<Physics> stepper(problem.grid, problem.boundaries, stepper_options(s));
      auto& p = problem.particles;
      stepper.rebuild(p, problem.materials);
      const double courant = s.time.courant_auto ? 0.5 : s.time.courant;
      const double dt = courant * problem.grid.cell_size.minCoeff() / problem.max_wave_speed();
      if (!(dt > 0)) std::abort();
      for (int k = 0; k < 5; ++k) {
        stepper.step(p.state, p.mass, k * dt, dt);
        if (s.particles_move) {
          p.position += dt * p.state.template bottomRows<Physics::dim>();
          stepper.rebuild(p, problem.materials);
        }
      }
      return 0;
    }
    Simulation<Physics> sim(s);
    for (int k = 0; k < 5 && sim.time() < s.time.end; ++k) {
      const double dt = std::min(sim.stable_time_step(), s.time.end - sim.time());
      if (!(dt > 0)) std::abort();  // a valid scene must give a positive time step
      sim.step(dt);
    }
    if (!std::isfinite(sim.energy())) std::abort();  // step() throws before a non-finite state
    return 0;
  });
}

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  const std::string text(reinterpret_cast<const char*>(data), size);
  ++reach.inputs;
  scene::Scene s;
  try {
    s = scene::parse_scene_text(text, "fuzz.json");
  } catch (const scene::SceneError&) {
    return 0;  // refused, with a message
  }
  ++reach.valid;
  if (!small_enough(s)) return 0;
  s.output.directory.clear();  // never write
  try {
    run_a_few_steps(s);
    ++reach.stepped;
  } catch (const std::exception&) {  // refused at set-up, or a run that fails with a message
  }
  return 0;
}
