// SPDX-License-Identifier: MIT
// Bounding volume hierarchy over a deforming triangle mesh (thesis section 4.3-4.5): a binary
// tree whose per-level volume kind (sphere, sphere+AABB, AABB) comes from a BvhSchedule, built
// once and refitted bottom-up after the vertices move.
//
// Split rule: object median. A node's triangles are split at the median of their centroids along
// the longest axis of the centroid bounds (std::nth_element, O(n) per node, O(n log n) total).
// Why not SAH: the thesis's schedule fixes the volume kind per *level* and the depth (11 levels
// for <= 10 triangles per leaf over ~9300 triangles), which presumes a balanced tree: the median
// split gives exactly ceil(log2(#T / leaf size)) + 1 levels and equal subtree sizes, so every
// level of the schedule covers the whole mesh. SAH makes unbalanced trees whose depth the
// schedule cannot predict, and its advantage is for a fixed geometry: after refit on a deforming
// liver the cost model it optimised is stale anyway.
//
// Depth limit: a node on the last level of the schedule becomes a leaf whatever it holds, so a
// mesh with more than max_leaf_triangles * 2^(levels - 1) triangles gets leaves larger than the
// limit (counted in BvhBuildInfo::oversize_leaves). Nothing is dropped; queries stay exact, the
// leaf tests just cost more.
//
// Volumes and refit: every node keeps its AABB (min/max over its vertices, exact). The sphere of a
// node whose kind has one depends on what the sphere is for:
//  - the node's box is tested too (a hybrid node, or a sphere level with the schedule's
//    box_tie_breaker): the sphere is only the early-out in front of the box, so it is the box's
//    circumsphere (collision/sphere_aabb.h). It is not stored: the query tests two circumspheres
//    straight from the boxes (circumspheres_overlap, no square root), so the refit of a hybrid
//    tree is exactly that of an AABB tree. Why: storing it cost a square root per node and
//    refit, 3.7 % of the whole frame in table 4.2 at 0 pairs, for a sphere that can never
//    reject a pair its box does not (the box lies inside it);
//  - the sphere is the node's only test (the all-sphere tree): stored, centred at the box
//    centre c, with the tightest radius for that centre at leaves (max |v - c| over the leaf's
//    vertices), and at internal nodes the max over children of min(|c - c_child| + r_child,
//    distance from c to the child's farthest box corner), each bound valid for the whole
//    subtree, so containment holds by construction, at O(1) per internal node instead of
//    O(subtree).
// Either way the radius is never larger than the box's circumsphere (tested), and all radii are
// padded (collision/sphere.h) so that round-off never makes a sphere miss a vertex.
// Refit visits nodes in reverse creation order (children are created after their parent) and
// reads each vertex of a leaf once (leaves keep their unique vertex list).
#pragma once

#include "collision/aabb.h"
#include "collision/bvh_schedule.h"
#include "collision/sphere.h"
#include "collision/sphere_aabb.h"

#include <Eigen/Core>

#include <cstdint>
#include <span>
#include <vector>

namespace softbench::collision {

struct BvhNode {
  Aabb box;       ///< kept in every node; the descent order uses it
  Sphere sphere;  ///< stored for sphere-only nodes (has_sphere() && !has_box()); see sphere_of()
  int first = 0;  ///< internal: index of the left child (right = first + 1); leaf: first slot
  int count = 0;  ///< leaf: number of triangles (> 0); internal: 0
  int vertex_first = 0;  ///< leaf: first entry in Bvh::leaf_vertices()
  int vertex_count = 0;  ///< leaf: number of unique vertices
  std::uint8_t level = 0;
  VolumeKind kind = VolumeKind::kAabb;
  bool box_tested = true;  ///< BvhSchedule::tests_box(level)

  bool is_leaf() const { return count > 0; }
  bool has_sphere() const { return kind != VolumeKind::kAabb; }
  /// Whether queries test the box (it is kept in every node; see BvhSchedule::box_tie_breaker).
  bool has_box() const { return box_tested; }
  /// The node's sphere (has_sphere() nodes): the stored one, or for a box-tested node the box's
  /// circumsphere, formed here.
  Sphere sphere_of() const { return has_box() ? circumsphere(box) : sphere; }
};

/// Shape of a built tree, for tests and reports.
struct BvhBuildInfo {
  int levels = 0;  ///< deepest level + 1
  int leaves = 0;
  int max_leaf_triangles = 0;
  int oversize_leaves = 0;  ///< leaves above the schedule's limit (depth limit reached)
};

class Bvh {
 public:
  Bvh() = default;
  /// Builds over `triangles` (3 x #T vertex indices into `positions`, 3 x #V, m) and fits the
  /// volumes to `positions`. Throws InputError for an invalid schedule (no levels, more than
  /// BvhSchedule::kMaxLevels, leaf size < 1), a vertex index out of range or a non-finite
  /// position.
  Bvh(const Eigen::Matrix3Xd& positions, const Eigen::Matrix3Xi& triangles, BvhSchedule schedule);

  /// Refits every volume to `positions` (3 x #V, same vertex count as at build), bottom-up,
  /// keeping the topology. Cost O(#V + #nodes); no allocation.
  void refit(const Eigen::Matrix3Xd& positions);

  const std::vector<BvhNode>& nodes() const { return nodes_; }
  bool empty() const { return nodes_.empty(); }
  const BvhSchedule& schedule() const { return schedule_; }
  const BvhBuildInfo& info() const { return info_; }
  int num_vertices() const { return num_vertices_; }
  /// The largest coordinate magnitude at the last refit (the root box's): what
  /// circumspheres_overlap needs to bound its round-off, kept so a query does not recompute it.
  double coordinate_magnitude() const { return coordinate_magnitude_; }
  int num_triangles() const { return static_cast<int>(slot_triangle_.size()); }

  /// Original triangle indices of a leaf.
  std::span<const int> leaf_triangles(const BvhNode& leaf) const {
    return {slot_triangle_.data() + leaf.first, static_cast<std::size_t>(leaf.count)};
  }
  /// Vertex indices of the triangle in `slot` (slots are leaf order; slot_triangle maps them
  /// back to the mesh's triangle index). Kept in slot order for locality in the leaf tests.
  const Eigen::Matrix3Xi& slot_vertices() const { return slot_vertices_; }
  int slot_triangle(int slot) const { return slot_triangle_[static_cast<std::size_t>(slot)]; }
  /// Unique vertex indices of a leaf.
  std::span<const int> leaf_vertices(const BvhNode& leaf) const {
    return {leaf_vertices_.data() + leaf.vertex_first, static_cast<std::size_t>(leaf.vertex_count)};
  }

 private:
  BvhSchedule schedule_;
  BvhBuildInfo info_;
  int num_vertices_ = 0;
  double coordinate_magnitude_ = 0.0;
  std::vector<BvhNode> nodes_;
  std::vector<int> slot_triangle_;
  Eigen::Matrix3Xi slot_vertices_;
  std::vector<int> leaf_vertices_;
};

}  // namespace softbench::collision
