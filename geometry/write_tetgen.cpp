// SPDX-License-Identifier: MIT
#include "geometry/atomic_file.h"
#include "geometry/mesh_io.h"
#include "geometry/tetgen_files.h"
#include "geometry/text_writer.h"

#include <system_error>

namespace softbench {
namespace {

// "index n1 n2 ..." per cell, 0-based like the .node file.
template <typename Cells>
void write_cells(std::ostream& out, const Cells& cells) {
  for (Eigen::Index c = 0; c < cells.cols(); ++c) {
    out << c;
    for (Eigen::Index k = 0; k < cells.rows(); ++k) {
      out << ' ' << cells(k, c);
    }
    out << '\n';
  }
}

// read_tetgen() reads base.ele and base.face whenever they exist, so one left over from an
// earlier mesh with the same base would be read with this one: remove it.
void write_or_remove(const std::filesystem::path& path,
                     bool has_cells,
                     const std::function<void(std::ostream&)>& write_content) {
  if (has_cells) {
    write_file_atomically(path, write_content);
    return;
  }
  std::error_code ignored;
  std::filesystem::remove(path, ignored);
}

}  // namespace

void write_tetgen(const std::filesystem::path& base, const MeshData& mesh) {
  write_file_atomically(tetgen_file(base, ".node"), [&mesh](std::ostream& out) {
    out << mesh.vertices.cols() << " 3 0 0\n";
    for (Eigen::Index v = 0; v < mesh.vertices.cols(); ++v) {
      out << v << ' ';
      write_xyz(out, mesh.vertices.col(v));
      out << '\n';
    }
  });
  write_or_remove(tetgen_file(base, ".ele"), mesh.tetrahedra.cols() > 0,
                  [&mesh](std::ostream& out) {
                    out << mesh.tetrahedra.cols() << " 4 0\n";
                    write_cells(out, mesh.tetrahedra);
                  });
  write_or_remove(tetgen_file(base, ".face"), mesh.triangles.cols() > 0,
                  [&mesh](std::ostream& out) {
                    out << mesh.triangles.cols() << " 0\n";
                    write_cells(out, mesh.triangles);
                  });
}

}  // namespace softbench
