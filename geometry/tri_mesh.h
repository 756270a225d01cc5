// SPDX-License-Identifier: MIT
#pragma once

#include <Eigen/Core>

namespace softbench {

/// A triangle surface. Outward orientation (counter-clockwise seen from outside) is the
/// convention wherever a closed surface is meant; functions that need it say so.
struct TriMesh {
  Eigen::Matrix3Xd vertices;   ///< 3 x #V, m
  Eigen::Matrix3Xi triangles;  ///< 3 x #T, vertex indices

  int num_vertices() const { return static_cast<int>(vertices.cols()); }
  int num_triangles() const { return static_cast<int>(triangles.cols()); }
};

}  // namespace softbench
