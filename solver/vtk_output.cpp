#include "solver/vtk_output.hpp"

#include "solver/output.hpp"

#include <cmath>
#include <ostream>

namespace dgmpm::vtk {

void write_points(const std::string& path, const Eigen::MatrixXd& positions,
                  const std::vector<PointData>& data) {
  const Eigen::Index n = positions.cols();
  output::write_atomically(path, [&](std::ostream& out) {
    out << "<?xml version=\"1.0\"?>\n"
        << "<VTKFile type=\"UnstructuredGrid\" version=\"1.0\" byte_order=\"LittleEndian\" "
           "header_type=\"UInt64\">\n"
        << "<UnstructuredGrid>\n<Piece NumberOfPoints=\"" << n << "\" NumberOfCells=\"" << n
        << "\">\n<PointData>\n";
    for (const PointData& d : data) {
      out << "<DataArray type=\"Float64\" Name=\"" << d.name << "\" NumberOfComponents=\""
          << d.components << "\" format=\"ascii\">\n";
      for (std::size_t k = 0; k < d.values.size(); ++k)
        out << d.values[k] << ((k + 1) % static_cast<std::size_t>(d.components) ? ' ' : '\n');
      out << "</DataArray>\n";
    }
    out << "</PointData>\n<Points>\n"
        << "<DataArray type=\"Float64\" NumberOfComponents=\"3\" format=\"ascii\">\n";
    for (Eigen::Index i = 0; i < n; ++i) {
      for (int k = 0; k < 3; ++k)
        out << (k < positions.rows() ? positions(k, i) : 0.0) << (k < 2 ? ' ' : '\n');
    }
    out << "</DataArray>\n</Points>\n<Cells>\n"
        << "<DataArray type=\"Int64\" Name=\"connectivity\" format=\"ascii\">\n";
    for (Eigen::Index i = 0; i < n; ++i) out << i << '\n';
    out << "</DataArray>\n<DataArray type=\"Int64\" Name=\"offsets\" format=\"ascii\">\n";
    for (Eigen::Index i = 0; i < n; ++i) out << i + 1 << '\n';
    out << "</DataArray>\n<DataArray type=\"UInt8\" Name=\"types\" format=\"ascii\">\n";
    for (Eigen::Index i = 0; i < n; ++i) out << "1\n";  // VTK_VERTEX
    out << "</DataArray>\n</Cells>\n</Piece>\n</UnstructuredGrid>\n</VTKFile>\n";
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
