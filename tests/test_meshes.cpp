// SPDX-License-Identifier: MIT
#include "tests/test_meshes.h"

#include "geometry/mesh_validation.h"
#include "geometry/shape_meshes.h"

#include <Eigen/Geometry>
#include <unistd.h>

#include <atomic>
#include <fstream>
#include <stdexcept>
#include <vector>

namespace softbench::test {
namespace {

// Flips tets whose vertex order gives a negative volume, so every helper returns positive tets.
void orient_positively(MeshData& mesh) {
  for (Eigen::Index t = 0; t < mesh.tetrahedra.cols(); ++t) {
    auto tet = mesh.tetrahedra.col(t);
    const Eigen::Vector3d a = mesh.vertices.col(tet(1)) - mesh.vertices.col(tet(0));
    const Eigen::Vector3d b = mesh.vertices.col(tet(2)) - mesh.vertices.col(tet(0));
    const Eigen::Vector3d c = mesh.vertices.col(tet(3)) - mesh.vertices.col(tet(0));
    if (a.dot(b.cross(c)) < 0) {
      std::swap(tet(2), tet(3));
    }
  }
}

Eigen::Matrix3Xd unit_cube_corners() {
  // Corner i has coordinates (bit 0, bit 1, bit 2) of i.
  Eigen::Matrix3Xd corners(3, 8);
  for (int i = 0; i < 8; ++i) {
    corners.col(i) << (i & 1), (i >> 1) & 1, (i >> 2) & 1;
  }
  return corners;
}

}  // namespace

MeshData single_tet() {
  MeshData mesh;
  mesh.vertices.resize(3, 4);
  mesh.vertices << 0, 1, 0, 0,  //
      0, 0, 1, 0,               //
      0, 0, 0, 1;
  mesh.tetrahedra.resize(4, 1);
  mesh.tetrahedra << 0, 1, 2, 3;
  mesh.source = "single_tet";
  return mesh;
}

MeshData cube_five_tets() {
  MeshData mesh;
  mesh.vertices = unit_cube_corners();
  mesh.tetrahedra.resize(4, 5);
  // Four corner tets around the corners with an even number of set bits, and the regular
  // central tet on the other four corners.
  mesh.tetrahedra << 0, 3, 5, 6, 1,  //
      1, 1, 1, 2, 2,                 //
      2, 2, 4, 4, 4,                 //
      4, 7, 7, 7, 7;
  mesh.source = "cube_five_tets";
  orient_positively(mesh);
  return mesh;
}

MeshData box_tets(int nx, int ny, int nz, double lx, double ly, double lz) {
  return softbench::box_tets(nx, ny, nz, lx, ly, lz);
}

MeshData cube_surface() {
  MeshData mesh;
  mesh.vertices = unit_cube_corners();
  mesh.triangles.resize(3, 12);
  // Two triangles per face, counter-clockwise seen from outside.
  mesh.triangles << 0, 0, 4, 4, 0, 0, 2, 2, 0, 0, 1, 1,  //
      2, 3, 5, 7, 1, 5, 6, 7, 4, 6, 3, 7,                //
      3, 1, 7, 6, 5, 4, 7, 3, 6, 2, 7, 5;
  mesh.source = "cube_surface";
  return mesh;
}

TempDir::TempDir() {
  static std::atomic<int> counter{0};
  path_ = std::filesystem::temp_directory_path()
          / ("softbench_test_" + std::to_string(::getpid()) + "_" + std::to_string(counter++));
  std::filesystem::remove_all(path_);
  std::filesystem::create_directories(path_);
}

TempDir::~TempDir() {
  std::error_code ignored;
  std::filesystem::remove_all(path_, ignored);
}

std::filesystem::path TempDir::write(const std::string& name, const std::string& content) const {
  const auto file = path_ / name;
  std::ofstream out(file, std::ios::binary);
  out << content;
  if (!out) {
    throw std::runtime_error("cannot write test file " + file.string());
  }
  return file;
}

const TetMesh& liver_like_box() {
  static const TetMesh mesh = make_tet_mesh(box_tets(4, 3, 2, 0.2, 0.15, 0.1));
  return mesh;
}

}  // namespace softbench::test
