#include "solver/output.hpp"

#include <filesystem>
#include <stdexcept>
#include <unistd.h>

namespace dgmpm::output {

namespace fs = std::filesystem;

namespace {
std::string temporary_name(const std::string& path) {
  return path + ".part-" + std::to_string(::getpid());
}
}  // namespace

void create_directories(const std::string& directory) {
  std::error_code ec;
  fs::create_directories(directory, ec);
  if (ec)
    throw std::runtime_error("cannot create output directory " + directory + ": " + ec.message());
}

void write_atomically(const std::string& path, const std::function<void(std::ostream&)>& fill) {
  const std::string tmp = temporary_name(path);
  {
    std::ofstream out(tmp);
    if (!out) throw std::runtime_error("cannot write " + tmp);
    out.precision(17);
    fill(out);
    out.flush();
    if (!out) {
      std::error_code ec;
      fs::remove(tmp, ec);
      throw std::runtime_error("error while writing " + tmp);
    }
  }
  std::error_code ec;
  fs::rename(tmp, path, ec);
  if (ec) throw std::runtime_error("cannot rename " + tmp + " to " + path + ": " + ec.message());
}

StreamedFile::StreamedFile(const std::string& path)
    : path_(path), temporary_(temporary_name(path)), stream_(temporary_) {
  if (!stream_) throw std::runtime_error("cannot write " + temporary_);
  stream_.precision(17);
}

void StreamedFile::close() {
  if (!stream_.is_open()) return;
  stream_.close();
  if (!stream_) throw std::runtime_error("error while writing " + temporary_);
  std::error_code ec;
  fs::rename(temporary_, path_, ec);
  if (ec)
    throw std::runtime_error("cannot rename " + temporary_ + " to " + path_ + ": " + ec.message());
}

StreamedFile::~StreamedFile() {
  if (stream_.is_open()) {
    stream_.close();
    std::error_code ec;
    fs::remove(temporary_, ec);
  }
}

}  // namespace dgmpm::output
