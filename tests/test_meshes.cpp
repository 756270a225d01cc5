// SPDX-License-Identifier: MIT
#include "tests/test_meshes.h"

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
  MeshData mesh;
  const auto vertex_index = [&](int i, int j, int k) { return i + (nx + 1) * (j + (ny + 1) * k); };
  mesh.vertices.resize(3, (nx + 1) * (ny + 1) * (nz + 1));
  for (int k = 0; k <= nz; ++k) {
    for (int j = 0; j <= ny; ++j) {
      for (int i = 0; i <= nx; ++i) {
        mesh.vertices.col(vertex_index(i, j, k)) << lx * i / nx, ly * j / ny, lz * k / nz;
      }
    }
  }
  // Kuhn's split: the six tets along the main diagonal, one per ordering of the axes. Every cube
  // uses the same diagonal direction, so neighbouring cubes share face diagonals (conforming).
  const int axis_orders[6][3] = {{0, 1, 2}, {0, 2, 1}, {1, 0, 2}, {1, 2, 0}, {2, 0, 1}, {2, 1, 0}};
  std::vector<Eigen::Vector4i> tets;
  for (int k = 0; k < nz; ++k) {
    for (int j = 0; j < ny; ++j) {
      for (int i = 0; i < nx; ++i) {
        for (const auto& order : axis_orders) {
          Eigen::Vector3i corner(i, j, k);
          Eigen::Vector4i tet;
          tet(0) = vertex_index(corner.x(), corner.y(), corner.z());
          for (int step = 0; step < 3; ++step) {
            corner(order[step]) += 1;
            tet(step + 1) = vertex_index(corner.x(), corner.y(), corner.z());
          }
          tets.push_back(tet);
        }
      }
    }
  }
  mesh.tetrahedra.resize(4, static_cast<Eigen::Index>(tets.size()));
  for (std::size_t t = 0; t < tets.size(); ++t) {
    mesh.tetrahedra.col(static_cast<Eigen::Index>(t)) = tets[t];
  }
  mesh.source = "box_tets";
  orient_positively(mesh);
  return mesh;
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

}  // namespace softbench::test
