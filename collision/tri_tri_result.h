// SPDX-License-Identifier: MIT
#pragma once

#include <Eigen/Core>

#include <cstdint>

namespace softbench::collision {

/// How two triangles meet, as every triangle-triangle test in collision/ reports it.
/// Closed-set semantics: triangles that only touch (a shared vertex, a vertex on the other's
/// edge or face, an edge lying in the other's plane) intersect.
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

}  // namespace softbench::collision
