#include "solver/output.hpp"

#include <nlohmann/json.hpp>

#include <fcntl.h>
#include <sys/file.h>
#include <unistd.h>

#include <cerrno>
#include <csignal>
#include <cstring>
#include <filesystem>
#include <stdexcept>
#include <utility>

namespace dgmpm::output {

namespace fs = std::filesystem;

namespace {
std::string temporary_name(const std::string& path) {
  return path + ".part-" + std::to_string(::getpid());
}

// Temporary files being written, removed by SIGINT / SIGTERM / SIGHUP before the process ends
// (the handler may only call async-signal-safe functions: fixed buffers, unlink, raise). With a
// stop handler (set_stop_handler), the first signal goes to it instead and the process lives on
// to write its record; a second one ends it as without.
constexpr int kSlots = 8;
constexpr std::size_t kPathBytes = 4096;
char pending[kSlots][kPathBytes];
volatile std::sig_atomic_t in_use[kSlots];
void (*volatile stop_handler)(int) = nullptr;
volatile std::sig_atomic_t stop_asked = 0;

extern "C" void remove_pending_and_die(int signal) {
  if (stop_handler && !stop_asked) {
    stop_asked = 1;
    stop_handler(signal);
    return;
  }
  for (int k = 0; k < kSlots; ++k)
    if (in_use[k]) ::unlink(pending[k]);
  std::signal(signal, SIG_DFL);
  std::raise(signal);
}

void install_signal_handlers() {
  static const bool installed = [] {
    for (int signal : {SIGINT, SIGTERM, SIGHUP}) std::signal(signal, remove_pending_and_die);
    return true;
  }();
  (void)installed;
}

int register_pending(const std::string& path) {
  install_signal_handlers();
  if (path.size() >= kPathBytes) return -1;
  for (int k = 0; k < kSlots; ++k)
    if (!in_use[k]) {
      std::memcpy(pending[k], path.c_str(), path.size() + 1);
      in_use[k] = 1;
      return k;
    }
  return -1;
}

void unregister_pending(int slot) {
  if (slot >= 0) in_use[slot] = 0;
}

// particles_NNN.csv / .vtu, particles.pvd, outputs.csv, energy.csv, summary.json.
bool is_run_output(const std::string& name) {
  if (name == "particles.pvd" || name == "outputs.csv" || name == "energy.csv" ||
      name == "summary.json")
    return true;
  const std::string prefix = "particles_";
  if (name.size() < prefix.size() + 5 || name.compare(0, prefix.size(), prefix) != 0) return false;
  const std::string ext = name.substr(name.size() - 4);
  const std::string digits = name.substr(prefix.size(), name.size() - prefix.size() - 4);
  return (ext == ".csv" || ext == ".vtu") &&
         digits.find_first_not_of("0123456789") == std::string::npos;
}

std::string reason() {
  return errno ? std::string(": ") + std::strerror(errno) : std::string();
}
}  // namespace

void set_stop_handler(void (*handler)(int)) {
  stop_handler = handler;
  install_signal_handlers();
}

void create_directories(const std::string& directory) {
  std::error_code ec;
  fs::create_directories(directory, ec);
  if (ec)
    throw std::runtime_error("cannot create output directory " + directory + ": " + ec.message());
}

void write_atomically(const std::string& path, const std::function<void(std::ostream&)>& fill) {
  const std::string tmp = temporary_name(path);
  const int slot = register_pending(tmp);
  std::error_code ec;
  try {
    std::ofstream out(tmp, std::ios::binary);  // binary VTU writes raw bytes
    errno = 0;
    if (!out) throw std::runtime_error("cannot write " + tmp + reason());
    out.precision(17);
    fill(out);
    out.flush();
    if (!out) throw std::runtime_error("error while writing " + tmp + reason());
    out.close();
    if (!out) throw std::runtime_error("error while writing " + tmp + reason());
    fs::rename(tmp, path, ec);
    if (ec) throw std::runtime_error("cannot rename " + tmp + " to " + path + ": " + ec.message());
  } catch (...) {
    fs::remove(tmp, ec);  // every failure path, the fill's own exceptions included
    unregister_pending(slot);
    throw;
  }
  unregister_pending(slot);
}

DirectoryClaim::DirectoryClaim(const std::string& directory, const std::string& scene,
                               const std::vector<std::string>& files, bool overwrite, bool resume)
    : directory_(directory), scene_path_(fs::absolute(scene).lexically_normal().string()) {
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
    take_over(files, overwrite, resume);
  } catch (...) {
    ::close(lock_fd_);  // a constructor that throws runs no destructor
    lock_fd_ = -1;
    throw;
  }
}

void DirectoryClaim::take_over(const std::vector<std::string>& files, bool overwrite,
                               bool resume) const {
  const std::string& directory = directory_;
  const std::string& scene_path = scene_path_;
  const std::string manifest = directory + "/manifest.json";
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
  } else if (!overwrite && !resume) {
    // Outputs of a run that left no manifest (an older dgmpm, or a copy): not ours to delete.
    for (const auto& entry : fs::directory_iterator(directory, ec))
      if (is_run_output(entry.path().filename().string()))
        throw std::runtime_error("output directory " + directory + " holds dgmpm outputs (" +
                                 entry.path().filename().string() +
                                 ") of an unknown run; write elsewhere (--out) or replace them "
                                 "(--overwrite)");
  }
  if (!resume)
    for (const auto& f : earlier)  // names only: never outside the directory
      if (fs::path(f).filename() == fs::path(f)) fs::remove(fs::path(directory) / f, ec);
  record(files);
}

void DirectoryClaim::record(const std::vector<std::string>& files) const {
  const nlohmann::json m{{"scene", scene_path_}, {"files", files}};
  write_atomically(directory_ + "/manifest.json",
                   [&](std::ostream& out) { out << m.dump(2) << '\n'; });
}

void CommittedFile::create(const std::string& path) {
  path_ = path;
  errno = 0;
  std::ofstream out(path, std::ios::binary | std::ios::trunc);
  if (!out) throw std::runtime_error("cannot write " + path + reason());
  buffer_.str("");
  buffer_.precision(17);
  bytes_ = 0;
  hash_ = Fnv1a();
}

bool CommittedFile::resume(const std::string& path, std::uint64_t bytes, std::uint64_t hash) {
  std::error_code ec;
  const auto size = fs::file_size(path, ec);
  if (ec || size < bytes) return false;
  std::ifstream in(path, std::ios::binary);
  std::string head(bytes, '\0');
  if (!in.read(head.data(), static_cast<std::streamsize>(bytes))) return false;
  Fnv1a h;
  h.add(head.data(), head.size());
  if (h.value != hash) return false;
  in.close();
  fs::resize_file(path, bytes, ec);
  if (ec)
    throw std::runtime_error("cannot cut " + path + " back to the checkpoint: " + ec.message());
  path_ = path;
  buffer_.str("");
  buffer_.precision(17);
  bytes_ = bytes;
  hash_.value = hash;
  return true;
}

void CommittedFile::commit() {
  const std::string rows = buffer_.str();
  if (rows.empty()) return;
  errno = 0;
  std::ofstream out(path_, std::ios::binary | std::ios::app);
  out.write(rows.data(), static_cast<std::streamsize>(rows.size()));
  out.flush();
  if (!out) throw std::runtime_error("error while writing " + path_ + reason());
  bytes_ += rows.size();
  hash_.add(rows.data(), rows.size());
  buffer_.str("");
}

DirectoryClaim::~DirectoryClaim() {
  if (lock_fd_ >= 0) ::close(lock_fd_);  // releases the lock; the file stays (harmless)
}

}  // namespace dgmpm::output
