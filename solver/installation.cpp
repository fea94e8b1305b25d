#include "solver/installation.hpp"

#include <cstdlib>
#include <filesystem>
#include <stdexcept>

namespace dgmpm {

namespace fs = std::filesystem;

const char* version() {
  return DGMPM_VERSION;
}

std::string data_directory() {
  if (const char* dir = std::getenv("DGMPM_DATA_DIR"); dir && *dir) return dir;
  std::error_code ec;
  const fs::path exe = fs::read_symlink("/proc/self/exe", ec);
  if (ec)
    throw std::runtime_error("cannot find the running binary (/proc/self/exe): " + ec.message());
  return (exe.parent_path().parent_path() / "share" / "dgmpm").lexically_normal().string();
}

std::string data_file(const std::string& relative) {
  const fs::path path = fs::path(data_directory()) / relative;
  std::error_code ec;
  if (!fs::exists(path, ec))
    throw std::runtime_error("dgmpm's data file " + path.string() +
                             " is missing (the binary looks in <its folder>/../share/dgmpm, or in "
                             "$DGMPM_DATA_DIR)");
  return path.string();
}

}  // namespace dgmpm
