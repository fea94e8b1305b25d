#pragma once
// Output files. Every file is written under a temporary name in its final directory and renamed
// when complete, so a reader never sees half a file; the temporary file is removed on every
// failure path and when SIGINT or SIGTERM ends the process.

#include <fstream>
#include <functional>
#include <string>
#include <vector>

namespace dgmpm::output {

// Writes `path` through `fill` (a stream on a temporary file), then renames. Throws
// std::runtime_error naming the path when the file cannot be written.
void write_atomically(const std::string& path, const std::function<void(std::ostream&)>& fill);

// A file written progressively (a history); renamed to its name by close().
class StreamedFile {
 public:
  StreamedFile() = default;
  explicit StreamedFile(const std::string& path);
  StreamedFile(StreamedFile&&) noexcept;
  StreamedFile& operator=(StreamedFile&&) noexcept;
  ~StreamedFile();  // an unfinished file is removed, never left under its final name
  bool is_open() const { return stream_.is_open(); }
  std::ostream& stream() { return stream_; }
  void close();

 private:
  void discard();  // closes and removes the temporary file
  std::string path_, temporary_;
  std::ofstream stream_;
  int slot_ = -1;  // registered for removal on SIGINT / SIGTERM
};

void create_directories(const std::string& directory);

// A run owns its output directory while it runs (an exclusive lock on DIR/.dgmpm.lock, released
// when the process ends, however it ends) and records in DIR/manifest.json the scene and the
// files it writes. Claiming a directory: refused while another run holds it; refused when it
// holds another scene's outputs (its manifest names another scene, or output files without a
// manifest) unless `overwrite`; then the files of the earlier run's manifest are removed, so a
// run of the same scene replaces exactly the earlier run's files.
class DirectoryClaim {
 public:
  DirectoryClaim(const std::string& directory, const std::string& scene,
                 const std::vector<std::string>& files, bool overwrite);
  ~DirectoryClaim();
  DirectoryClaim(const DirectoryClaim&) = delete;
  DirectoryClaim& operator=(const DirectoryClaim&) = delete;

 private:
  static void take_over(const std::string& directory, const std::string& scene,
                        const std::vector<std::string>& files, bool overwrite);
  int lock_fd_ = -1;
};

}  // namespace dgmpm::output
