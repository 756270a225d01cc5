// SPDX-License-Identifier: MIT
#pragma once

#include "geometry/mesh_data.h"

#include <string>
#include <utility>
#include <vector>

namespace softbench {

/// What a reader has parsed so far. Readers append as they go (never reserving from a count the
/// file claims, unless checked against the file size) and pack the result into MeshData once.
struct MeshBuilder {
  std::vector<double> coordinates;  ///< x y z of each vertex
  std::vector<int> triangles;       ///< 3 vertex indices per triangle, 0-based
  std::vector<int> tetrahedra;      ///< 4 vertex indices per tet, 0-based

  int vertex_count() const { return static_cast<int>(coordinates.size() / 3); }
  void add_vertex(double x, double y, double z) {
    coordinates.insert(coordinates.end(), {x, y, z});
  }
  void add_triangle(int a, int b, int c) { triangles.insert(triangles.end(), {a, b, c}); }
  void add_tetrahedron(int a, int b, int c, int d) {
    tetrahedra.insert(tetrahedra.end(), {a, b, c, d});
  }

  MeshData finish(std::string source) const {
    MeshData mesh;
    mesh.vertices = Eigen::Map<const Eigen::Matrix3Xd>(coordinates.data(), 3,
                                                       static_cast<Eigen::Index>(vertex_count()));
    mesh.triangles = Eigen::Map<const Eigen::Matrix3Xi>(
        triangles.data(), 3, static_cast<Eigen::Index>(triangles.size() / 3));
    mesh.tetrahedra = Eigen::Map<const Eigen::Matrix4Xi>(
        tetrahedra.data(), 4, static_cast<Eigen::Index>(tetrahedra.size() / 4));
    mesh.source = std::move(source);
    return mesh;
  }
};

}  // namespace softbench
