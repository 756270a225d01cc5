// SPDX-License-Identifier: MIT
#include "geometry/mesh_io.h"
#include "geometry/text_tokenizer.h"

#include <string>

namespace softbench {

MeshData read_mesh(const std::filesystem::path& path) {
  const std::string extension = lowercase_extension(path);
  if (extension == ".obj") {
    return read_obj(path);
  }
  if (extension == ".msh") {
    return read_msh(path);
  }
  if (extension == ".node" || extension == ".ele" || extension == ".face") {
    return read_tetgen(path);
  }
  if (extension == ".stl") {
    return read_stl(path);
  }
  if (extension == ".vtk") {
    return read_vtk(path);
  }
  if (extension == ".vtu") {
    return read_vtu(path);
  }
  const std::string problem = extension.empty()
                                  ? std::string("no file extension")
                                  : concat("unknown mesh file extension ", quoted_token(extension));
  throw_file_error(
      path.string(),
      concat(problem, " (expected .obj, .msh, .node, .ele, .face, .stl, .vtk or .vtu)"));
}

}  // namespace softbench
