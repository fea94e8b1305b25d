#include "reports/report_io.hpp"

#include "solver/installation.hpp"
#include "solver/output.hpp"

#include <spawn.h>
#include <sys/wait.h>

#include <cmath>
#include <iomanip>
#include <ostream>
#include <sstream>

extern char** environ;

namespace dgmpm::report {

double seconds_since(clock_type::time_point start) {
  return std::chrono::duration<double>(clock_type::now() - start).count();
}

std::string num(double x) {
  if (std::isnan(x)) return "nan";
  std::ostringstream s;
  s << std::setprecision(10) << x;
  return s.str();
}

std::string fixed(double x, int digits) {
  if (std::isnan(x)) return "n/a";
  std::ostringstream s;
  s << std::setprecision(digits) << std::fixed << x;
  return s.str();
}

std::string sci(double x, int digits) {
  if (std::isnan(x)) return "n/a";
  std::ostringstream s;
  s << std::setprecision(digits) << std::scientific << x;
  return s.str();
}

void write_file(const std::string& dir, const std::string& name, std::vector<std::string>& files,
                const std::function<void(std::ostream&)>& fill) {
  const std::string path = dir + "/" + name;
  output::write_atomically(path, fill);
  files.push_back(path);
}

int run_python(const std::string& script_name, const std::vector<std::string>& arguments,
               std::ostream& log) {
  const std::string python = DGMPM_PYTHON;
  const std::string script = data_file("reports/" + script_name);
  std::vector<std::string> args = {python, script};
  args.insert(args.end(), arguments.begin(), arguments.end());
  std::vector<char*> argv;
  for (auto& a : args) argv.push_back(a.data());
  argv.push_back(nullptr);
  pid_t pid;
  if (python.empty() ||
      ::posix_spawn(&pid, python.c_str(), nullptr, nullptr, argv.data(), environ) != 0) {
    log << "cannot start the plotting script with '" << python << "'\n";
    return 127;
  }
  int status = 0;
  if (::waitpid(pid, &status, 0) < 0) return 127;
  return WIFEXITED(status) ? WEXITSTATUS(status) : 128;
}

}  // namespace dgmpm::report
