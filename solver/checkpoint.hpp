#pragma once
// Checkpoint files: the complete state of a run, enough for a restart to continue bit for bit.
//
// Layout: the line "DGMPM checkpoint\n"; a little-endian uint64 length and that many bytes of
// JSON (the header: format, dgmpm version, the scene's document, the run's scalars, stored as the
// bit patterns of the doubles); a uint64 length and the payload (the particle arrays, raw); a
// uint64 FNV-1a hash of everything before it. Files are written atomically (output.hpp).

#include "solver/scene.hpp"

#include <cstdint>
#include <cstring>
#include <nlohmann/json.hpp>
#include <string>

namespace dgmpm::checkpoint {

// 2: initial positions only for moving particles with an exact solution; 3: for all moving
// particles (their displacement is an output); 4: the range of Courant numbers run and the
// largest wave speed (finite strain: they change with the state).
inline constexpr int kFormat = 4;

struct File {
  nlohmann::json header;
  std::string payload;
};

// Throws std::runtime_error naming the path when it cannot be written.
void write(const std::string& path, const File& file);
// Throws scene::SceneError (an input error) naming the path: unreadable, not a checkpoint,
// truncated or corrupt (hash), or of another format.
File read(const std::string& path);

// Refuses (scene::SceneError) a checkpoint written by another dgmpm version, or of another scene:
// the scene's document must be the checkpoint's but for output.directory; the message names the
// first key that differs.
void check_compatible(const std::string& path, const nlohmann::json& header,
                      const scene::Scene& scene);
// The part of a scene's document a checkpoint must match.
nlohmann::json scene_identity(const scene::Scene& scene);

inline std::uint64_t bits(double x) {
  std::uint64_t u;
  std::memcpy(&u, &x, sizeof u);
  return u;
}
inline double from_bits(std::uint64_t u) {
  double x;
  std::memcpy(&x, &u, sizeof x);
  return x;
}

// Raw arrays into and out of a payload, in order.
class PayloadWriter {
 public:
  explicit PayloadWriter(std::string& out) : out_(out) {}
  void bytes(const void* data, std::size_t n) { out_.append(static_cast<const char*>(data), n); }

 private:
  std::string& out_;
};

class PayloadReader {
 public:
  PayloadReader(const std::string& path, const std::string& in) : path_(path), in_(in) {}
  void bytes(void* data, std::size_t n);  // SceneError when the payload is too short
  void expect_end() const;                // SceneError when bytes are left over

 private:
  const std::string& path_;
  const std::string& in_;
  std::size_t at_ = 0;
};

}  // namespace dgmpm::checkpoint
