// SPDX-License-Identifier: MIT
#pragma once

#include "geometry/mesh_data.h"
#include "geometry/tet_mesh.h"

#include <filesystem>
#include <string>

// Small meshes made in code, shared by every test executable. Tests read no file outside the
// repository.
namespace softbench::test {

/// The unit right-angled tet (0,0,0) (1,0,0) (0,1,0) (0,0,1), positively oriented, volume 1/6.
MeshData single_tet();
/// The unit cube [0,1]^3 split into 5 tets (one central regular tet), positively oriented.
MeshData cube_five_tets();
/// A box [0,lx]x[0,ly]x[0,lz] of nx*ny*nz cubes, each split into 6 tets (Kuhn), conforming
/// (geometry/shape_meshes.h builds it).
MeshData box_tets(int nx, int ny, int nz, double lx = 1.0, double ly = 1.0, double lz = 1.0);

/// A 20 x 15 x 10 cm box of 5 cm cells: a liver-sized test body (built once).
const TetMesh& liver_like_box();
/// The closed, outward-oriented surface of the unit cube: 8 vertices, 12 triangles.
MeshData cube_surface();

/// A fresh empty directory under the system temp dir, removed when the object dies.
class TempDir {
 public:
  TempDir();
  ~TempDir();
  TempDir(const TempDir&) = delete;
  TempDir& operator=(const TempDir&) = delete;
  const std::filesystem::path& path() const { return path_; }
  /// Writes `content` to path()/name and returns the full path.
  std::filesystem::path write(const std::string& name, const std::string& content) const;

 private:
  std::filesystem::path path_;
};

}  // namespace softbench::test
