#include "solver/checkpoint.hpp"

#include "solver/output.hpp"

#include <fstream>
#include <sstream>
#include <stdexcept>
#include <string>
#include <vector>

namespace dgmpm::checkpoint {

namespace {

constexpr char kMagic[] = "DGMPM checkpoint\n";
constexpr std::size_t kMagicBytes = sizeof kMagic - 1;

void put_u64(std::string& s, std::uint64_t v) {
  for (int k = 0; k < 8; ++k) s.push_back(static_cast<char>((v >> (8 * k)) & 0xff));
}

std::uint64_t get_u64(const std::string& s, std::size_t at) {
  std::uint64_t v = 0;
  for (int k = 7; k >= 0; --k) v = (v << 8) | static_cast<unsigned char>(s[at + k]);
  return v;
}

std::string format_number(double v) {  // the fewest digits that read back as v
  std::string text;
  for (int digits = 6; digits <= 17; ++digits) {
    std::ostringstream s;
    s.precision(digits);
    s << v;
    text = s.str();
    if (std::stod(text) == v) break;
  }
  return text;
}

scene::SceneError refused(const std::string& path, const std::string& why) {
  return scene::SceneError(path + ": cannot restart from this checkpoint: " + why);
}

}  // namespace

void write(const std::string& path, const File& file) {
  std::string bytes(kMagic, kMagicBytes);
  const std::string header = file.header.dump();
  put_u64(bytes, header.size());
  bytes += header;
  put_u64(bytes, file.payload.size());
  bytes += file.payload;
  output::Fnv1a hash;
  hash.add(bytes.data(), bytes.size());
  put_u64(bytes, hash.value);
  output::write_atomically(path, [&](std::ostream& out) {
    out.write(bytes.data(), static_cast<std::streamsize>(bytes.size()));
  });
}

File read(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  if (!in) throw refused(path, "cannot read it");
  std::ostringstream text;
  text << in.rdbuf();
  const std::string s = text.str();
  if (s.size() < kMagicBytes || s.compare(0, kMagicBytes, kMagic) != 0)
    throw refused(path, "not a dgmpm checkpoint (no \"DGMPM checkpoint\" line at its start)");
  const std::size_t minimum = kMagicBytes + 3 * 8;
  if (s.size() < minimum) throw refused(path, "truncated");
  output::Fnv1a hash;
  hash.add(s.data(), s.size() - 8);
  if (hash.value != get_u64(s, s.size() - 8))
    throw refused(path, "truncated or corrupt (its hash does not match its contents)");
  const std::uint64_t header_bytes = get_u64(s, kMagicBytes);
  if (header_bytes > s.size() - minimum) throw refused(path, "corrupt header length");
  const std::size_t payload_at = kMagicBytes + 8 + header_bytes;
  const std::uint64_t payload_bytes = get_u64(s, payload_at);
  if (payload_bytes != s.size() - payload_at - 16) throw refused(path, "corrupt payload length");
  File file;
  try {
    file.header = nlohmann::json::parse(s.substr(kMagicBytes + 8, header_bytes));
  } catch (const nlohmann::json::exception& e) {
    throw refused(path, std::string("unreadable header: ") + e.what());
  }
  if (!file.header.is_object() || !file.header.contains("format") ||
      file.header["format"] != kFormat)
    throw refused(path, "checkpoint format " +
                            (file.header.is_object() && file.header.contains("format")
                                 ? file.header["format"].dump()
                                 : std::string("unknown")) +
                            ", this dgmpm reads format " + std::to_string(kFormat));
  file.payload = s.substr(payload_at + 8, payload_bytes);
  return file;
}

nlohmann::json scene_identity(const scene::Scene& scene) {
  nlohmann::json doc = scene.document;
  if (doc.is_object() && doc.contains("output") && doc["output"].is_object())
    doc["output"].erase("directory");
  return doc;
}

void check_compatible(const std::string& path, const nlohmann::json& header,
                      const scene::Scene& scene) {
  const std::string version = header.value("version", std::string("unknown"));
  if (version != DGMPM_VERSION)
    throw refused(path,
                  "written by dgmpm " + version +
                      ", this is dgmpm " DGMPM_VERSION
                      " (a restart continues bit for bit only with the version that wrote it)");
  nlohmann::json recorded = header.value("scene", nlohmann::json());
  const nlohmann::json current = scene_identity(scene);
  if (recorded == current) return;
  // An extended run: a later time.end, and output times that keep those up to the checkpoint.
  const double at = from_bits(header.value("time", std::uint64_t{0}));
  const auto key_of = [](const nlohmann::json& doc, const char* object, const char* key) {
    const auto o = doc.find(object);
    return o != doc.end() && o->is_object() && o->contains(key) ? (*o)[key] : nlohmann::json();
  };
  const auto times = [&](const nlohmann::json& doc, double end) {
    std::vector<double> kept;  // the output times up to the checkpoint (default: the end time)
    const nlohmann::json t = key_of(doc, "output", "times");
    for (const auto& x : t.is_array() ? t : nlohmann::json::array({end}))
      if (x.is_number() && x.get<double>() <= at) kept.push_back(x.get<double>());
    return kept;
  };
  const nlohmann::json old_end = key_of(recorded, "time", "end");
  if (recorded.is_object() && old_end.is_number()) {
    const double end = scene.time.end, before = old_end.get<double>();
    if (end != before && !(end > at))
      throw refused(path, "time.end: value " + format_number(end) +
                              " is not after the checkpoint's time " + format_number(at) +
                              "; allowed: a later end time, which extends the run");
    if (times(recorded, before) == times(current, end)) {
      recorded["time"]["end"] = current["time"]["end"];  // the rest must be the same
      if (current.contains("output") && current["output"].contains("times"))
        recorded["output"]["times"] = current["output"]["times"];
      else if (recorded.contains("output") && recorded["output"].is_object())
        recorded["output"].erase("times");
      if (recorded == current) return;
    }
  }
  const nlohmann::json patch = nlohmann::json::diff(recorded, current);
  std::string key = patch.empty() ? std::string("/") : patch[0].value("path", std::string("/"));
  throw refused(path, "it was written by a run of another scene (" +
                          header.value("scene_source", std::string("?")) + "); " + scene.source +
                          " differs at " + key +
                          " (a restart needs the same scene but for output.directory, a later "
                          "time.end and output times that keep those up to the checkpoint)");
}

void PayloadReader::bytes(void* data, std::size_t n) {
  if (n > in_.size() - at_) throw refused(path_, "its payload is shorter than its header says");
  std::memcpy(data, in_.data() + at_, n);
  at_ += n;
}

void PayloadReader::expect_end() const {
  if (at_ != in_.size()) throw refused(path_, "its payload is longer than its header says");
}

}  // namespace dgmpm::checkpoint
