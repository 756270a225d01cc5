// SPDX-License-Identifier: MIT
#include "geometry/atomic_file.h"
#include "geometry/mesh_io.h"
#include "geometry/text_tokenizer.h"
#include "geometry/text_writer.h"
#include "geometry/vtk_cells.h"

#include <stdexcept>
#include <string>
#include <string_view>

// VTK XML UnstructuredGrid with ASCII arrays: larger than binary, but readable, diffable, and
// read back exactly by read_vtu().
namespace softbench {
namespace {

std::string xml_escaped(std::string_view text) {
  std::string escaped;
  for (const char c : text) {
    switch (c) {
      case '&':
        escaped += "&amp;";
        break;
      case '<':
        escaped += "&lt;";
        break;
      case '>':
        escaped += "&gt;";
        break;
      case '"':
        escaped += "&quot;";
        break;
      default:
        escaped += c;
    }
  }
  return escaped;
}

// One vector (column) per line: point coordinates or a vertex field.
void write_vectors(std::ostream& out, const Eigen::Matrix3Xd& vectors) {
  for (Eigen::Index v = 0; v < vectors.cols(); ++v) {
    out << "          ";
    write_xyz(out, vectors.col(v));
    out << '\n';
  }
}

template <typename Cells>
void write_connectivity(std::ostream& out, const Cells& cells) {
  for (Eigen::Index c = 0; c < cells.cols(); ++c) {
    out << "          ";
    for (Eigen::Index k = 0; k < cells.rows(); ++k) {
      out << cells(k, c) << (k + 1 < cells.rows() ? " " : "\n");
    }
  }
}

void open_array(std::ostream& out, std::string_view type, std::string_view name, int components) {
  out << "        <DataArray type=\"" << type << '"';
  if (!name.empty()) {
    out << " Name=\"" << xml_escaped(name) << '"';
  }
  if (components > 1) {
    out << " NumberOfComponents=\"" << components << '"';
  }
  out << " format=\"ascii\">\n";
}

constexpr std::string_view kCloseArray = "        </DataArray>\n";

}  // namespace

void write_vtu(const std::filesystem::path& path,
               const MeshData& mesh,
               std::span<const VertexField> fields) {
  for (const VertexField& field : fields) {
    if (field.values == nullptr || field.values->cols() != mesh.vertices.cols()) {
      throw std::invalid_argument(
          concat("write_vtu: field '", field.name, "' must be 3 x ", mesh.vertices.cols()));
    }
  }
  const Eigen::Index tets = mesh.tetrahedra.cols();
  const Eigen::Index triangles = mesh.triangles.cols();
  write_file_atomically(path, [&](std::ostream& out) {
    out << "<?xml version=\"1.0\"?>\n"
        << "<VTKFile type=\"UnstructuredGrid\" version=\"0.1\" byte_order=\"LittleEndian\">\n"
        << "  <UnstructuredGrid>\n"
        << "    <Piece NumberOfPoints=\"" << mesh.vertices.cols() << "\" NumberOfCells=\""
        << tets + triangles << "\">\n";
    if (!fields.empty()) {
      out << "      <PointData>\n";
      for (const VertexField& field : fields) {
        open_array(out, "Float64", field.name, 3);
        write_vectors(out, *field.values);
        out << kCloseArray;
      }
      out << "      </PointData>\n";
    }
    out << "      <Points>\n";
    open_array(out, "Float64", "", 3);
    write_vectors(out, mesh.vertices);
    out << kCloseArray << "      </Points>\n";

    // Tets first, then triangles; offsets are where each cell's connectivity ends.
    out << "      <Cells>\n";
    open_array(out, "Int64", "connectivity", 1);
    write_connectivity(out, mesh.tetrahedra);
    write_connectivity(out, mesh.triangles);
    out << kCloseArray;
    open_array(out, "Int64", "offsets", 1);
    for (Eigen::Index c = 0; c < tets + triangles; ++c) {
      out << "          " << (c < tets ? 4 * (c + 1) : 4 * tets + 3 * (c - tets + 1)) << '\n';
    }
    out << kCloseArray;
    open_array(out, "UInt8", "types", 1);
    for (Eigen::Index c = 0; c < tets + triangles; ++c) {
      out << "          " << (c < tets ? kVtkTetra : kVtkTriangle) << '\n';
    }
    out << kCloseArray << "      </Cells>\n";
    out << "    </Piece>\n  </UnstructuredGrid>\n</VTKFile>\n";
  });
}

}  // namespace softbench
