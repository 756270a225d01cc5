// SPDX-License-Identifier: MIT
#pragma once

#include <Eigen/Core>

#include <string>

namespace softbench {

/// What a mesh file holds, as read and before validation. Any part may be empty: a surface file
/// has no tetrahedra, a TetGen .node file alone has neither. Indices are 0-based whatever the
/// file's own convention.
struct MeshData {
  Eigen::Matrix3Xd vertices;    ///< 3 x #V, in the file's units
  Eigen::Matrix3Xi triangles;   ///< 3 x #T, vertex indices
  Eigen::Matrix4Xi tetrahedra;  ///< 4 x #tets, vertex indices, as ordered in the file
  std::string source;           ///< the file it came from, for messages
};

}  // namespace softbench
