// SPDX-License-Identifier: MIT
#pragma once

#include <Eigen/Core>

#include <vector>

namespace softbench {

struct WeldedVertices {
  Eigen::Matrix3Xd vertices;  ///< 3 x #welded, in order of first appearance
  std::vector<int> index_of;  ///< for each input point, its welded vertex
};

/// Merges points closer than `relative_tolerance` times the diagonal of their bounding box (>= 0;
/// 0 merges exact duplicates only) into the first such point seen, as a triangle soup (STL) needs
/// to become a mesh. A hash grid of cells at least the tolerance wide keeps this O(n): only the
/// 27 cells around a point can hold a partner. The squared diagonal must be a finite double
/// (read_stl refuses points spread further).
WeldedVertices weld_vertices(const Eigen::Ref<const Eigen::Matrix3Xd>& points,
                             double relative_tolerance);

}  // namespace softbench
