// SPDX-License-Identifier: MIT
#include "geometry/atomic_file.h"
#include "geometry/mesh_io.h"
#include "geometry/text_writer.h"

namespace softbench {

// Only vertices and triangles: OBJ has no volume elements, so tetrahedra are not written.
void write_obj(const std::filesystem::path& path, const MeshData& mesh) {
  write_file_atomically(path, [&mesh](std::ostream& out) {
    out << "# softbench: " << mesh.vertices.cols() << " vertices, " << mesh.triangles.cols()
        << " triangles\n";
    for (Eigen::Index v = 0; v < mesh.vertices.cols(); ++v) {
      out << "v ";
      write_xyz(out, mesh.vertices.col(v));
      out << '\n';
    }
    for (Eigen::Index t = 0; t < mesh.triangles.cols(); ++t) {
      out << "f " << mesh.triangles(0, t) + 1 << ' ' << mesh.triangles(1, t) + 1 << ' '
          << mesh.triangles(2, t) + 1 << '\n';
    }
  });
}

}  // namespace softbench
