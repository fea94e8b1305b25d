#pragma once
#include <CLI/CLI.hpp>

#include <functional>
#include <iosfwd>
#include <string>
#include <vector>

namespace dgmpm::stability {

// What a query runs once its input is validated: everything; only the quick analyses (1D
// layouts: milliseconds); nothing (the fuzzer, tests of the refusals).
enum class CourantAnalysis { all, quick, none };

// Registers `dgmpm courant` on the application.
void add_courant_command(CLI::App& app);
// The same, printing to the given streams. A failing run ends the parse with CLI::RuntimeError
// carrying its exit code.
void add_courant_command(CLI::App& app, std::ostream& out, std::ostream& err);
void add_courant_command(CLI::App& app, std::ostream& out, std::ostream& err,
                         CourantAnalysis analysis);

// `--scene SCENE.json` analyses a whole scene, which needs the solver (above stability/ in the
// layering): the entry point installs it. Returns the exit code.
using SceneAnalysis =
    std::function<int(const std::string& scene, bool json, std::ostream& out, std::ostream& err)>;
void set_scene_analysis(SceneAnalysis analysis);

// Runs `dgmpm courant ARGS...` (args without the program and subcommand names) and returns the
// exit code: 0 on success, 2 for invalid input (message on err), CLI11's codes for parse errors.
int courant_main(const std::vector<std::string>& args, std::ostream& out, std::ostream& err,
                 CourantAnalysis analysis = CourantAnalysis::all);

}  // namespace dgmpm::stability
