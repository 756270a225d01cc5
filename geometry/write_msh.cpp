// SPDX-License-Identifier: MIT
#include "geometry/atomic_file.h"
#include "geometry/mesh_io.h"
#include "geometry/text_writer.h"

namespace softbench {
namespace {

constexpr int kGmshTriangle = 2;
constexpr int kGmshTetrahedron = 4;

// "elm-number elm-type number-of-tags physical elementary node-numbers...", 1-based. Every element
// gets physical and elementary tag 1: Gmsh and meshio expect the two tags to be present.
template <typename Cells>
void write_elements(std::ostream& out, const Cells& cells, int type, Eigen::Index& number) {
  for (Eigen::Index c = 0; c < cells.cols(); ++c) {
    out << ++number << ' ' << type << " 2 1 1";
    for (Eigen::Index k = 0; k < cells.rows(); ++k) {
      out << ' ' << cells(k, c) + 1;
    }
    out << '\n';
  }
}

}  // namespace

void write_msh(const std::filesystem::path& path, const MeshData& mesh) {
  write_file_atomically(path, [&mesh](std::ostream& out) {
    out << "$MeshFormat\n2.2 0 8\n$EndMeshFormat\n";
    out << "$Nodes\n" << mesh.vertices.cols() << '\n';
    for (Eigen::Index v = 0; v < mesh.vertices.cols(); ++v) {
      out << v + 1 << ' ';
      write_xyz(out, mesh.vertices.col(v));
      out << '\n';
    }
    out << "$EndNodes\n";
    out << "$Elements\n" << mesh.triangles.cols() + mesh.tetrahedra.cols() << '\n';
    Eigen::Index number = 0;
    write_elements(out, mesh.triangles, kGmshTriangle, number);
    write_elements(out, mesh.tetrahedra, kGmshTetrahedron, number);
    out << "$EndElements\n";
  });
}

}  // namespace softbench
