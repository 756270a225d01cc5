// SPDX-License-Identifier: MIT
#pragma once

// Batched triangle-triangle tests for the leaf-vs-leaf stage of a BVH query: pair i is a[i]
// against b[i], triangles stored as structure-of-arrays so that blocks of lanes run without
// branches (collision/tri_tri_batch_lanes.h): 8 lanes with AVX-512, 4 with AVX2 or baseline
// SSE2, chosen at run time.
//
// Per lane: the scalar projection test's certified floating-point path (collision/
// tri_tri_projection.cpp with the bounds of tri_tri_projection_bounds.h): B's vertices against
// A's plane and case (b), the V and W rejections of L_B, A's vertices against B's plane, and
// the order of the chord and L_B on the intersection line. A lane whose signs or comparisons the
// bounds cannot certify (touching, coplanar, degenerate, within rounding of a decision) is
// re-tested by the exact scalar tri_tri_projection, so the answers equal it on every input.

#include <Eigen/Core>

#include <cstddef>
#include <cstdint>
#include <span>
#include <vector>

namespace softbench::collision {

/// Triangles as structure-of-arrays: vertex k of triangle i is (xk[i], yk[i], zk[i]).
struct TriangleSoA {
  std::vector<double> x0, y0, z0, x1, y1, z1, x2, y2, z2;

  std::size_t size() const { return x0.size(); }
  void reserve(std::size_t n);
  void clear();
  void push_back(const Eigen::Vector3d& v0, const Eigen::Vector3d& v1, const Eigen::Vector3d& v2);
  Eigen::Vector3d vertex(std::size_t i, int k) const;
};

struct BatchStats {
  std::size_t pairs = 0;
  std::size_t exact_fallbacks = 0;  ///< lanes re-tested by the scalar exact projection test
};

/// intersect[i] = tri_tri_projection(a[i], b[i]).intersect() for i < a.size() (a and b of equal
/// size, intersect at least that long).
BatchStats tri_tri_batch(const TriangleSoA& a,
                         const TriangleSoA& b,
                         std::span<std::uint8_t> intersect);

}  // namespace softbench::collision
