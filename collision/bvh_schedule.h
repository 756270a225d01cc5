// SPDX-License-Identifier: MIT
#pragma once

#include <cstdint>
#include <vector>

namespace softbench::collision {

/// Which bounding volume a BVH node carries and tests. The tree keeps a box in every node (the
/// sphere is centred on it, see bvh.h); the kind decides which tests the query runs.
enum class VolumeKind : std::uint8_t {
  kSphere,      ///< sphere test (then the box, if the schedule's box_tie_breaker is set)
  kSphereAabb,  ///< sphere test, then box test (the thesis's hybrid node)
  kAabb,        ///< box test only
};

/// How a BVH is shaped: the volume kind per level (level 0 = root) and the leaf-size and depth
/// limits. The number of levels is the depth limit: a node at level levels.size() - 1 becomes a
/// leaf whatever its size (see build_bvh).
struct BvhSchedule {
  std::vector<VolumeKind> levels;  ///< kind per level, root first; 1 to kMaxLevels entries
  int max_leaf_triangles = 10;     ///< split a node while it holds more triangles than this
  /// Sphere levels are still the early-out (a pair whose spheres miss is rejected without its
  /// boxes), but a pair whose spheres overlap is then decided by the exact box every node keeps
  /// anyway, so a sphere level never rejects less than a box level would. Why: in table 4.2 the
  /// top spheres around the long thin probe (80 mm radius) reject almost nothing, and the pairs
  /// they let through cost more node visits than the boxes would have. Set by layered() (the
  /// thesis's hybrid trees); off in uniform() so that the all-sphere peer tests spheres only.
  bool box_tie_breaker = false;

  static constexpr int kMaxLevels = 60;

  int max_levels() const { return static_cast<int>(levels.size()); }
  /// The kind at `level`; levels past the end (never built) repeat the last entry.
  VolumeKind kind_at(int level) const {
    return levels[static_cast<std::size_t>(level < max_levels() ? level : max_levels() - 1)];
  }

  /// Whether the query tests a node's box at `level`: its kind has one, or the tie-breaker.
  bool tests_box(int level) const {
    return kind_at(level) != VolumeKind::kSphere || box_tie_breaker;
  }

  /// `count` levels of one kind.
  static BvhSchedule uniform(VolumeKind kind, int count, int max_leaf_triangles) {
    return {std::vector<VolumeKind>(static_cast<std::size_t>(count), kind), max_leaf_triangles,
            false};
  }
  /// `spheres` sphere levels, then `hybrid` sphere+box levels, then `boxes` box levels.
  static BvhSchedule layered(int spheres, int hybrid, int boxes, int max_leaf_triangles) {
    BvhSchedule schedule;
    schedule.max_leaf_triangles = max_leaf_triangles;
    schedule.box_tie_breaker = true;
    schedule.levels.insert(schedule.levels.end(), static_cast<std::size_t>(spheres),
                           VolumeKind::kSphere);
    schedule.levels.insert(schedule.levels.end(), static_cast<std::size_t>(hybrid),
                           VolumeKind::kSphereAabb);
    schedule.levels.insert(schedule.levels.end(), static_cast<std::size_t>(boxes),
                           VolumeKind::kAabb);
    return schedule;
  }

  /// The thesis's liver tree (section 4.5): <= 10 triangles per leaf, 11 levels: 3 sphere,
  /// 3 sphere+AABB, 5 AABB.
  static BvhSchedule liver() { return layered(3, 3, 5, 10); }
  /// The thesis's instrument tree: 9 levels: 2 sphere, 2 sphere+AABB, 5 AABB; its leaf size is
  /// not stated, the liver's 10 is assumed.
  static BvhSchedule instrument() { return layered(2, 2, 5, 10); }
  /// Peers of table 4.2: the same depth and leaf size with one volume kind throughout.
  static BvhSchedule all_sphere(int count = 11, int max_leaf_triangles = 10) {
    return uniform(VolumeKind::kSphere, count, max_leaf_triangles);
  }
  static BvhSchedule all_aabb(int count = 11, int max_leaf_triangles = 10) {
    return uniform(VolumeKind::kAabb, count, max_leaf_triangles);
  }
};

}  // namespace softbench::collision
