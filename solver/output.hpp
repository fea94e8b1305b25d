#pragma once
// Output files. Every file is written under a temporary name in its final directory and renamed
// when complete, so a reader never sees half a file; the temporary file is removed on every
// failure path and when SIGINT or SIGTERM ends the process.

#include <charconv>
#include <cstdint>
#include <fstream>
#include <functional>
#include <sstream>
#include <string>
#include <vector>

namespace dgmpm::output {

// Writes `path` through `fill` (a stream on a temporary file), then renames. Throws
// std::runtime_error naming the path when the file cannot be written.
void write_atomically(const std::string& path, const std::function<void(std::ostream&)>& fill);

// Writes x as a stream of precision 17 does (printf's %.17g, the same bytes) without the stream's
// locale machinery: a particle table is millions of numbers, and their formatting was a fifth of
// an MPM run's instructions when it wrote one table (callgrind).
inline void write_number(std::ostream& out, double x) {
  char text[32];
  const auto end = std::to_chars(text, text + sizeof text, x, std::chars_format::general, 17).ptr;
  out.write(text, end - text);
}

// 64-bit FNV-1a, fed incrementally (checkpoints and the histories they record).
struct Fnv1a {
  std::uint64_t value = 14695981039346656037ull;
  void add(const void* data, std::size_t bytes) {
    const auto* b = static_cast<const unsigned char*>(data);
    for (std::size_t i = 0; i < bytes; ++i) value = (value ^ b[i]) * 1099511628211ull;
  }
};

// A history written as a run goes, under its own name: rows are kept in memory and appended to
// the file whole at each commit (outputs, checkpoints, every few seconds), so a killed run leaves
// complete rows up to its last commit. A checkpoint records the file's length and hash; a restart
// cuts the file back to that length.
class CommittedFile {
 public:
  void create(const std::string& path);  // a new, empty file
  // Continues the file as a checkpoint recorded it: true when its first `bytes` bytes hash to
  // `hash` (the file is cut there); false when it is missing, shorter or different.
  bool resume(const std::string& path, std::uint64_t bytes, std::uint64_t hash);
  std::ostream& stream() { return buffer_; }
  void commit();  // appends what was written since the last commit; throws naming the path
  std::uint64_t bytes() const { return bytes_; }
  std::uint64_t hash() const { return hash_.value; }

 private:
  std::string path_;
  std::ostringstream buffer_;
  std::uint64_t bytes_ = 0;
  Fnv1a hash_;
};

void create_directories(const std::string& directory);

// SIGINT, SIGTERM and SIGHUP call `handler` (async-signal-safe: it should only set a flag) the
// first time, and the process goes on; the second time the temporary files being written are
// removed and the signal ends the process. Without a handler, the first one does that.
void set_stop_handler(void (*handler)(int));

// A run owns its output directory while it runs (an exclusive lock on DIR/.dgmpm.lock, released
// when the process ends, however it ends) and records in DIR/manifest.json the scene and the
// files it writes. Claiming a directory: refused while another run holds it; refused when it
// holds another scene's outputs (its manifest names another scene, or output files without a
// manifest) unless `overwrite`; then the files of the earlier run's manifest are removed, so a
// run of the same scene replaces exactly the earlier run's files.
class DirectoryClaim {
 public:
  // `resume`: a restart continues the outputs it finds (nothing is removed).
  DirectoryClaim(const std::string& directory, const std::string& scene,
                 const std::vector<std::string>& files, bool overwrite, bool resume = false);
  ~DirectoryClaim();
  // Rewrites the manifest with these files (checkpoints are added as they are written).
  void record(const std::vector<std::string>& files) const;
  DirectoryClaim(const DirectoryClaim&) = delete;
  DirectoryClaim& operator=(const DirectoryClaim&) = delete;

 private:
  void take_over(const std::vector<std::string>& files, bool overwrite, bool resume) const;
  std::string directory_, scene_path_;
  int lock_fd_ = -1;
};

}  // namespace dgmpm::output
