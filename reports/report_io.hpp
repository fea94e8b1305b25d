#pragma once
// What the report's sections share: number formats for CSV and Markdown, atomic file writes
// recorded in the report's file list, the plotting scripts' launcher and a wall clock.
#include <chrono>
#include <functional>
#include <iosfwd>
#include <string>
#include <vector>

namespace dgmpm::report {

using clock_type = std::chrono::steady_clock;
double seconds_since(clock_type::time_point start);

// Full-precision numbers in CSV; "nan" for unavailable values (pandas-free reading in plot.py).
std::string num(double x);
// Markdown: fixed or scientific with `digits`; "n/a" for NaN.
std::string fixed(double x, int digits);
std::string sci(double x, int digits = 2);

// Writes dir/name atomically through `fill` and appends its path to `files`.
void write_file(const std::string& dir, const std::string& name, std::vector<std::string>& files,
                const std::function<void(std::ostream&)>& fill);

// Runs reports/<script> with `arguments` through Debian's python3; returns its exit status.
int run_python(const std::string& script_name, const std::vector<std::string>& arguments,
               std::ostream& log);

}  // namespace dgmpm::report
