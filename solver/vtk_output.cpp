#include "solver/vtk_output.hpp"

#include "solver/output.hpp"

#include <zlib.h>

#include <array>
#include <bit>
#include <cmath>
#include <cstdint>
#include <ostream>
#include <stdexcept>
#include <string>
#include <vector>

namespace dgmpm::vtk {

namespace {

static_assert(std::endian::native == std::endian::little, "the files say LittleEndian");

// One array of the appended section: its bytes, written after the XML.
struct Block {
  std::vector<char> bytes;
};
template <class T>
void append(Block& block, T value) {
  const auto* p = reinterpret_cast<const char*>(&value);
  block.bytes.insert(block.bytes.end(), p, p + sizeof(T));
}

// VTK's zlib layout of one array, as a single block: the header (UInt64s: block count, the
// block's size, the size of a last partial block (0: none), each block's compressed size), then
// the compressed bytes. zlib's fastest level: outputs of a million particles stay seconds.
void compress(Block& block) {
  const auto size = static_cast<uLong>(block.bytes.size());
  std::vector<char> packed(compressBound(size));
  uLongf packed_size = packed.size();
  if (size > 0 &&
      compress2(reinterpret_cast<Bytef*>(packed.data()), &packed_size,
                reinterpret_cast<const Bytef*>(block.bytes.data()), size, Z_BEST_SPEED) != Z_OK)
    throw std::runtime_error("zlib could not compress a VTU array");
  const std::uint64_t blocks = size > 0 ? 1 : 0;
  const std::array<std::uint64_t, 4> header{blocks, size, 0, size > 0 ? packed_size : 0};
  std::vector<char> out;
  const auto* h = reinterpret_cast<const char*>(header.data());
  out.insert(out.end(), h, h + (blocks > 0 ? 4 : 3) * sizeof(std::uint64_t));
  if (size > 0) out.insert(out.end(), packed.data(), packed.data() + packed_size);
  block.bytes.swap(out);
}

// Writes the arrays either inline as text or as references into the appended raw section, each
// compressed with zlib (the file's compressor attribute says so).
class ArrayWriter {
 public:
  ArrayWriter(std::ostream& out, bool binary) : out_(out), binary_(binary) {}

  // `attributes`: Name and NumberOfComponents as needed; `text` writes the values as ASCII.
  template <class Text, class Bytes>
  void array(const std::string& type, const std::string& attributes, Text&& text, Bytes&& bytes) {
    out_ << "<DataArray type=\"" << type << "\"" << attributes;
    if (!binary_) {
      out_ << " format=\"ascii\">\n";
      text(out_);
      out_ << "</DataArray>\n";
      return;
    }
    Block block;
    bytes(block);
    compress(block);
    out_ << " format=\"appended\" offset=\"" << offset_ << "\"/>\n";
    offset_ += block.bytes.size();
    blocks_.push_back(std::move(block));
  }
  void finish() {
    if (!binary_) return;
    out_ << "<AppendedData encoding=\"raw\">\n_";
    for (const Block& b : blocks_)
      out_.write(b.bytes.data(), static_cast<std::streamsize>(b.bytes.size()));
    out_ << "\n</AppendedData>\n";
  }

 private:
  std::ostream& out_;
  bool binary_;
  std::uint64_t offset_ = 0;
  std::vector<Block> blocks_;
};

// The FieldData's "units": one "name: unit" string per array with a unit, the points' and the
// time's, as VTK writes a string array in text (each string's bytes as numbers, then a 0).
void write_units(std::ostream& out, const std::vector<PointData>& data, bool time) {
  std::vector<std::string> entries;
  for (const PointData& d : data)
    if (!d.unit.empty()) entries.push_back(d.name + ": " + d.unit);
  entries.emplace_back("Points: m");
  if (time) entries.emplace_back("TimeValue: s");
  out << "<Array type=\"String\" Name=\"units\" NumberOfTuples=\"" << entries.size()
      << "\" format=\"ascii\">\n";
  for (const std::string& e : entries) {
    for (unsigned char c : e) out << static_cast<int>(c) << ' ';
    out << "0\n";
  }
  out << "</Array>\n";
}

}  // namespace

void write_points(const std::string& path, const Eigen::MatrixXd& positions,
                  const std::vector<PointData>& data, const VtuOptions& options) {
  const Eigen::Index n = positions.cols();
  output::write_atomically(path, [&](std::ostream& out) {
    out << "<?xml version=\"1.0\"?>\n"
        << "<VTKFile type=\"UnstructuredGrid\" version=\"1.0\" byte_order=\"LittleEndian\" "
           "header_type=\"UInt64\""
        << (options.binary ? " compressor=\"vtkZLibDataCompressor\"" : "") << ">\n"
        << "<UnstructuredGrid>\n";
    ArrayWriter arrays(out, options.binary);
    out << "<FieldData>\n";
    if (options.time)  // ParaView's time of a data set read on its own
      arrays.array(
          "Float64", " Name=\"TimeValue\" NumberOfTuples=\"1\"",
          [&](std::ostream& o) { o << *options.time << '\n'; },
          [&](Block& b) { append(b, *options.time); });
    write_units(out, data, options.time.has_value());
    out << "</FieldData>\n";
    out << "<Piece NumberOfPoints=\"" << n << "\" NumberOfCells=\"" << n << "\">\n<PointData>\n";
    for (const PointData& d : data) {
      arrays.array(
          "Float64",
          " Name=\"" + d.name + "\" NumberOfComponents=\"" + std::to_string(d.components) + "\"",
          [&](std::ostream& o) {
            for (std::size_t k = 0; k < d.values.size(); ++k) {
              output::write_number(o, d.values[k]);
              o.put((k + 1) % static_cast<std::size_t>(d.components) ? ' ' : '\n');
            }
          },
          [&](Block& b) {
            for (double v : d.values) append(b, v);
          });
    }
    out << "</PointData>\n<Points>\n";
    const auto coordinate = [&](Eigen::Index i, int k) {
      return k < positions.rows() ? positions(k, i) : 0.0;
    };
    arrays.array(
        "Float64", " NumberOfComponents=\"3\"",
        [&](std::ostream& o) {
          for (Eigen::Index i = 0; i < n; ++i)
            for (int k = 0; k < 3; ++k) {
              output::write_number(o, coordinate(i, k));
              o.put(k < 2 ? ' ' : '\n');
            }
        },
        [&](Block& b) {
          for (Eigen::Index i = 0; i < n; ++i)
            for (int k = 0; k < 3; ++k) append(b, coordinate(i, k));
        });
    out << "</Points>\n<Cells>\n";
    // One vertex cell per particle: connectivity i, offset i + 1, type 1 (VTK_VERTEX).
    const auto cells = [&](const char* name, std::int64_t shift) {
      arrays.array(
          "Int64", std::string(" Name=\"") + name + "\"",
          [&](std::ostream& o) {
            for (Eigen::Index i = 0; i < n; ++i) o << i + shift << '\n';
          },
          [&](Block& b) {
            for (Eigen::Index i = 0; i < n; ++i) append(b, static_cast<std::int64_t>(i + shift));
          });
    };
    cells("connectivity", 0);
    cells("offsets", 1);
    arrays.array(
        "UInt8", " Name=\"types\"",
        [&](std::ostream& o) {
          for (Eigen::Index i = 0; i < n; ++i) o << "1\n";
        },
        [&](Block& b) { b.bytes.assign(static_cast<std::size_t>(n), char{1}); });
    out << "</Cells>\n</Piece>\n</UnstructuredGrid>\n";
    arrays.finish();
    out << "</VTKFile>\n";
  });
}

void write_piece_index(const std::string& path, const std::vector<std::string>& pieces,
                       const std::vector<PointData>& data) {
  output::write_atomically(path, [&](std::ostream& out) {
    out << "<?xml version=\"1.0\"?>\n"
        << "<VTKFile type=\"PUnstructuredGrid\" version=\"1.0\" byte_order=\"LittleEndian\" "
           "header_type=\"UInt64\">\n"
        << "<PUnstructuredGrid GhostLevel=\"0\">\n<PPointData>\n";
    for (const PointData& d : data)
      out << "<PDataArray type=\"Float64\" Name=\"" << d.name << "\" NumberOfComponents=\""
          << d.components << "\"/>\n";
    out << "</PPointData>\n<PPoints>\n<PDataArray type=\"Float64\" NumberOfComponents=\"3\"/>\n"
        << "</PPoints>\n<PCells>\n<PDataArray type=\"Int64\" Name=\"connectivity\"/>\n"
        << "<PDataArray type=\"Int64\" Name=\"offsets\"/>\n"
        << "<PDataArray type=\"UInt8\" Name=\"types\"/>\n</PCells>\n";
    for (const auto& piece : pieces) out << "<Piece Source=\"" << piece << "\"/>\n";
    out << "</PUnstructuredGrid>\n</VTKFile>\n";
  });
}

void write_series(const std::string& path,
                  const std::vector<std::pair<double, std::string>>& files) {
  output::write_atomically(path, [&](std::ostream& out) {
    out << "<?xml version=\"1.0\"?>\n"
        << "<VTKFile type=\"Collection\" version=\"1.0\" byte_order=\"LittleEndian\">\n"
        << "<Collection>\n";
    for (const auto& [t, file] : files)
      out << "<DataSet timestep=\"" << t << "\" group=\"\" part=\"0\" file=\"" << file << "\"/>\n";
    out << "</Collection>\n</VTKFile>\n";
  });
}

}  // namespace dgmpm::vtk
