// SPDX-License-Identifier: MIT
#pragma once

#include <Eigen/Core>

#include <cstdint>

namespace softbench::collision {

/// The part of a triangle (a, b, c) = (vertex 0, 1, 2) a closest point lies on. Edge k runs from
/// vertex k to vertex (k + 1) % 3.
enum class TriangleFeature : std::uint8_t {
  kFace,
  kEdge01,
  kEdge12,
  kEdge20,
  kVertex0,
  kVertex1,
  kVertex2,
};

struct TrianglePoint {
  Eigen::Vector3d point = Eigen::Vector3d::Zero();
  /// Weights of vertices 0, 1, 2 (non-negative, sum 1): point = w0 a + w1 b + w2 c up to
  /// round-off.
  Eigen::Vector3d barycentric = Eigen::Vector3d(1.0, 0.0, 0.0);
  TriangleFeature feature = TriangleFeature::kFace;
};

/// The point of triangle (a, b, c) closest to `p`, and the feature it lies on, by Voronoi-region
/// classification (Ericson, Real-Time Collision Detection, 2005, section 5.1.5). Degenerate
/// triangles (zero-length edges, collinear vertices) are handled: the face region is empty for
/// them and the answer is the closest point of the three edges.
TrianglePoint closest_point_on_triangle(const Eigen::Vector3d& p,
                                        const Eigen::Vector3d& a,
                                        const Eigen::Vector3d& b,
                                        const Eigen::Vector3d& c);

}  // namespace softbench::collision
