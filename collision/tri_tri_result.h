// SPDX-License-Identifier: MIT
#pragma once

// The contract shared by every triangle-triangle test in collision/ (tri_tri_projection,
// tri_tri_moller, tri_tri_guigue; the batched path answers the intersect flag only):
//  - input: triangle A = (p0, p1, p2) and triangle B = (q0, q1, q2), world coordinates, finite;
//  - closed sets: triangles that only touch (a shared vertex, a vertex on the other's edge or
//    face, an edge lying in the other's plane) intersect;
//  - output: kDisjoint, kSegment with the segment [a, b] where they meet (a == b for a point
//    contact; end points in floating point), or kCoplanar when both lie in one plane and
//    overlap (no segment).
// Each header says how its test decides (plain double or exact signs) and what it does with
// degenerate (zero-area) triangles.

#include <Eigen/Core>

#include <cstdint>

namespace softbench::collision {

/// How two triangles meet.
enum class TriTriContact : std::uint8_t {
  kDisjoint,  ///< no common point
  kSegment,   ///< the triangles meet in the segment [a, b] (a == b for a single point)
  kCoplanar,  ///< both lie in one plane and their interiors or boundaries overlap; no segment
};

struct TriTriResult {
  TriTriContact contact = TriTriContact::kDisjoint;
  Eigen::Vector3d a = Eigen::Vector3d::Zero();  ///< segment end (kSegment only), world frame
  Eigen::Vector3d b = Eigen::Vector3d::Zero();  ///< segment end (kSegment only), world frame

  bool intersect() const { return contact != TriTriContact::kDisjoint; }
};

/// The signature of a function of a triangle pair (p0, p1, p2) x (q0, q1, q2): the tests
/// declare themselves as `TrianglePairFunction<TriTriResult> name;` (a function declaration).
template <typename Result>
using TrianglePairFunction = Result(const Eigen::Vector3d& p0,
                                    const Eigen::Vector3d& p1,
                                    const Eigen::Vector3d& p2,
                                    const Eigen::Vector3d& q0,
                                    const Eigen::Vector3d& q1,
                                    const Eigen::Vector3d& q2);

/// A triangle-triangle test (the shared contract above).
using TriTriTest = TrianglePairFunction<TriTriResult>;

}  // namespace softbench::collision
