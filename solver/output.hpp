#pragma once
// Output files. Every file is written under a temporary name in its final directory and renamed
// when complete, so a reader never sees half a file.

#include <fstream>
#include <functional>
#include <string>

namespace dgmpm::output {

// Writes `path` through `fill` (a stream on a temporary file), then renames. Throws
// std::runtime_error naming the path when the file cannot be written.
void write_atomically(const std::string& path, const std::function<void(std::ostream&)>& fill);

// A file written progressively (a history); renamed to its name by close().
class StreamedFile {
 public:
  StreamedFile() = default;
  explicit StreamedFile(const std::string& path);
  StreamedFile(StreamedFile&&) = default;
  StreamedFile& operator=(StreamedFile&&) = default;
  ~StreamedFile();  // an unfinished file is removed, never left under its final name
  bool is_open() const { return stream_.is_open(); }
  std::ostream& stream() { return stream_; }
  void close();

 private:
  std::string path_, temporary_;
  std::ofstream stream_;
};

void create_directories(const std::string& directory);

}  // namespace dgmpm::output
