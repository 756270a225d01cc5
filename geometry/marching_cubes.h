// SPDX-License-Identifier: MIT
#pragma once

#include "geometry/tri_mesh.h"

#include <Eigen/Core>

#include <vector>

namespace softbench {

/// A scalar field sampled on a regular grid: value(i, j, k) at origin + (i, j, k) .* spacing,
/// stored x-fastest. The thesis's CT volume is one of these (section 2.3).
struct ScalarGrid {
  Eigen::Vector3i size{0, 0, 0};     ///< samples along x, y, z
  Eigen::Vector3d origin{0, 0, 0};   ///< m, position of sample (0, 0, 0)
  Eigen::Vector3d spacing{1, 1, 1};  ///< m between samples
  std::vector<float> values;         ///< size.prod() samples

  float& at(int i, int j, int k) { return values[index(i, j, k)]; }
  float at(int i, int j, int k) const { return values[index(i, j, k)]; }
  std::size_t index(int i, int j, int k) const {
    return static_cast<std::size_t>(i)
           + static_cast<std::size_t>(size.x())
                 * (static_cast<std::size_t>(j) + static_cast<std::size_t>(size.y()) * k);
  }
  Eigen::Vector3d position(int i, int j, int k) const {
    return origin + Eigen::Vector3d(i, j, k).cwiseProduct(spacing);
  }
};

/// The iso-surface of `grid` at `iso_value` by marching cubes (Lorensen & Cline 1987; the thesis's
/// section 2.3): the iso-point on each cell edge by linear interpolation (thesis eq. 2-3).
/// Samples strictly greater than iso_value are inside. Vertices on shared cell edges are shared,
/// so a field whose inside region stays away from the grid border gives a closed, manifold,
/// outward-oriented surface.
/// `normals`, if given, receives per-vertex unit normals (3 x #V) interpolated from the central-
/// difference gradient at the cell corners (thesis eq. 2-2), pointing outward.
TriMesh marching_cubes(const ScalarGrid& grid,
                       float iso_value,
                       Eigen::Matrix3Xd* normals = nullptr);

}  // namespace softbench
