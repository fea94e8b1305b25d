#include "solver/output.hpp"

#include <nlohmann/json.hpp>

#include <fcntl.h>
#include <sys/file.h>
#include <unistd.h>

#include <cerrno>
#include <cstring>
#include <filesystem>
#include <regex>
#include <stdexcept>

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

DirectoryClaim::DirectoryClaim(const std::string& directory, const std::string& scene,
                               const std::vector<std::string>& files, bool overwrite) {
  const std::string lock = directory + "/.dgmpm.lock";
  lock_fd_ = ::open(lock.c_str(), O_CREAT | O_RDWR | O_CLOEXEC, 0644);
  if (lock_fd_ < 0)
    throw std::runtime_error("cannot lock output directory " + directory + ": " +
                             std::strerror(errno));
  if (::flock(lock_fd_, LOCK_EX | LOCK_NB) != 0) {
    ::close(lock_fd_);
    lock_fd_ = -1;
    throw std::runtime_error("output directory " + directory +
                             " is in use by another running dgmpm run; wait for it, or write "
                             "elsewhere (--out)");
  }
  try {
    take_over(directory, scene, files, overwrite);
  } catch (...) {
    ::close(lock_fd_);  // a constructor that throws runs no destructor
    lock_fd_ = -1;
    throw;
  }
}

void DirectoryClaim::take_over(const std::string& directory, const std::string& scene,
                               const std::vector<std::string>& files, bool overwrite) {
  const std::string manifest = directory + "/manifest.json";
  const std::string scene_path = fs::absolute(scene).lexically_normal().string();
  std::vector<std::string> earlier;
  std::error_code ec;
  if (fs::exists(manifest, ec)) {
    nlohmann::json m;
    try {
      std::ifstream in(manifest);
      m = nlohmann::json::parse(in);
      const std::string owner = m.at("scene").get<std::string>();
      if (owner != scene_path && !overwrite)
        throw std::runtime_error("output directory " + directory + " holds the outputs of " +
                                 owner + "; write elsewhere (--out) or replace them (--overwrite)");
      for (const auto& f : m.at("files")) earlier.push_back(f.get<std::string>());
    } catch (const nlohmann::json::exception&) {
      if (!overwrite)
        throw std::runtime_error("output directory " + directory +
                                 " has an unreadable manifest.json; --overwrite replaces it");
    }
  } else if (!overwrite) {
    // Outputs of a run that left no manifest (an older dgmpm, or a copy): not ours to delete.
    static const std::regex ours(
        R"((particles_\d+\.(csv|vtu)|particles\.pvd|energy\.csv|summary\.json))");
    for (const auto& entry : fs::directory_iterator(directory, ec))
      if (std::regex_match(entry.path().filename().string(), ours))
        throw std::runtime_error("output directory " + directory + " holds dgmpm outputs (" +
                                 entry.path().filename().string() +
                                 ") of an unknown run; write elsewhere (--out) or replace them "
                                 "(--overwrite)");
  }
  for (const auto& f : earlier)  // names only: never outside the directory
    if (fs::path(f).filename() == fs::path(f)) fs::remove(fs::path(directory) / f, ec);
  nlohmann::json m{{"scene", scene_path}, {"files", files}};
  write_atomically(manifest, [&](std::ostream& out) { out << m.dump(2) << '\n'; });
}

DirectoryClaim::~DirectoryClaim() {
  if (lock_fd_ >= 0) ::close(lock_fd_);  // releases the lock; the file stays (harmless)
}

}  // namespace dgmpm::output
