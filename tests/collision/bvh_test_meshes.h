// SPDX-License-Identifier: MIT
#pragma once

#include "geometry/shape_meshes.h"
#include "geometry/tri_mesh.h"

#include <Eigen/Core>
#include <Eigen/Geometry>

#include <cmath>
#include <map>
#include <random>
#include <tuple>
#include <utility>
#include <vector>

// Closed, outward-oriented test surfaces made in code for the BVH and mesh-distance tests.
namespace softbench::collision::test {

/// The icosphere of geometry/shape_meshes.h: `levels` subdivisions of an icosahedron, on a sphere
/// of `radius` about the origin, closed and outward oriented.
using ::softbench::icosphere;

/// The surface of the box [0, size.x] x [0, size.y] x [0, size.z], each face an n x n grid of
/// squares split into two triangles. Closed and outward oriented.
inline TriMesh box_surface(int n, const Eigen::Vector3d& size = Eigen::Vector3d::Ones()) {
  std::map<std::tuple<int, int, int>, int> index;
  std::vector<Eigen::Vector3d> vertices;
  std::vector<Eigen::Vector3i> triangles;
  auto vertex = [&](const Eigen::Vector3i& lattice) {
    const auto [it, inserted] = index.try_emplace({lattice.x(), lattice.y(), lattice.z()},
                                                  static_cast<int>(vertices.size()));
    if (inserted) {
      vertices.push_back(lattice.cast<double>().cwiseProduct(size) / n);
    }
    return it->second;
  };
  for (int axis = 0; axis < 3; ++axis) {
    const int u = (axis + 1) % 3, v = (axis + 2) % 3;
    for (int side = 0; side < 2; ++side) {
      for (int i = 0; i < n; ++i) {
        for (int j = 0; j < n; ++j) {
          Eigen::Vector3i corner[4];
          for (int k = 0; k < 4; ++k) {
            corner[k][axis] = side * n;
            corner[k][u] = i + (k == 1 || k == 2);
            corner[k][v] = j + (k >= 2);
          }
          // (u, v, axis) is right-handed, so u-then-v turns counter-clockwise seen from +axis.
          int c[4];
          for (int k = 0; k < 4; ++k) {
            c[k] = vertex(corner[k]);
          }
          if (side == 1) {
            triangles.emplace_back(c[0], c[1], c[2]);
            triangles.emplace_back(c[0], c[2], c[3]);
          } else {
            triangles.emplace_back(c[0], c[2], c[1]);
            triangles.emplace_back(c[0], c[3], c[2]);
          }
        }
      }
    }
  }
  TriMesh mesh;
  mesh.vertices.resize(3, static_cast<Eigen::Index>(vertices.size()));
  for (std::size_t i = 0; i < vertices.size(); ++i) {
    mesh.vertices.col(static_cast<Eigen::Index>(i)) = vertices[i];
  }
  mesh.triangles.resize(3, static_cast<Eigen::Index>(triangles.size()));
  for (std::size_t t = 0; t < triangles.size(); ++t) {
    mesh.triangles.col(static_cast<Eigen::Index>(t)) = triangles[t];
  }
  return mesh;
}

/// Moves every vertex radially (about the origin) by a factor in [1 - amount, 1 + amount].
inline void perturb_radially(TriMesh& mesh, double amount, std::mt19937& rng) {
  std::uniform_real_distribution<double> factor(1.0 - amount, 1.0 + amount);
  for (Eigen::Index i = 0; i < mesh.vertices.cols(); ++i) {
    mesh.vertices.col(i) *= factor(rng);
  }
}

/// Adds independent uniform noise in [-amount, amount] to every coordinate.
inline Eigen::Matrix3Xd jitter(const Eigen::Matrix3Xd& positions,
                               double amount,
                               std::mt19937& rng) {
  std::uniform_real_distribution<double> noise(-amount, amount);
  Eigen::Matrix3Xd moved = positions;
  for (Eigen::Index i = 0; i < moved.size(); ++i) {
    moved.data()[i] += noise(rng);
  }
  return moved;
}

inline Eigen::Matrix3d random_rotation(std::mt19937& rng) {
  std::normal_distribution<double> normal;
  // One draw a statement: the order a compiler evaluates a call's arguments in is unspecified
  // (GCC's last to first, which these draws keep; clang's first to last), and the tests' scenes
  // must not change with the compiler.
  const double z = normal(rng);
  const double y = normal(rng);
  const double x = normal(rng);
  const double w = normal(rng);
  Eigen::Quaterniond q(w, x, y, z);
  return q.normalized().toRotationMatrix();
}

}  // namespace softbench::collision::test
