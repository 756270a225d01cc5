// SPDX-License-Identifier: MIT
// Closest point on a triangle mesh and inside/outside of a closed mesh, for contact generation:
// a tissue vertex that ends up inside a rigid instrument is projected onto the instrument's
// surface.
//
// Closest point: branch and bound over a BVH: a stack-based depth-first descent that visits the
// nearer child first and skips nodes whose volume is farther than the best distance so far (a
// node's bound is the larger of its sphere and box distances, by its kind). Exact up to the
// round-off of the point-triangle distance (tests compare with brute force).
//
// Inside/outside: angle-weighted pseudonormals (Baerentzen & Aanaes, "Signed distance computation
// using the angle weighted pseudonormal", IEEE TVCG 11(3), 2005). For a closed, outward-oriented,
// manifold mesh, a point p is inside iff (p - c) . n < 0, where c is the closest point and n the
// pseudonormal of the feature c lies on: the face normal, for an edge the sum of its two faces'
// unit normals (each weighted by the angle pi), for a vertex the sum of its faces' unit normals
// weighted by their angles at it. Points on the surface (distance 0) are not inside. On open or
// non-manifold meshes the sign is meaningless (normals are still summed; no error is raised).
#pragma once

#include "collision/aabb.h"
#include "collision/bvh.h"
#include "collision/bvh_schedule.h"
#include "collision/closest_point_triangle.h"
#include "collision/query_stats.h"
#include "geometry/mesh_topology.h"

#include <Eigen/Core>

#include <limits>
#include <optional>
#include <vector>

namespace softbench::collision {

class MeshDistance {
 public:
  /// The mesh point closest to a query point.
  struct Nearest {
    int triangle = -1;                                ///< -1 for an empty mesh
    Eigen::Vector3d point = Eigen::Vector3d::Zero();  ///< m, the closest point
    /// Weights of the triangle's vertices 0, 1, 2 giving `point` (non-negative, sum 1).
    Eigen::Vector3d barycentric = Eigen::Vector3d(1.0, 0.0, 0.0);
    TriangleFeature feature = TriangleFeature::kFace;
    double distance = std::numeric_limits<double>::infinity();         ///< m, >= 0
    double signed_distance = std::numeric_limits<double>::infinity();  ///< m, < 0 inside
    /// Unit angle-weighted pseudonormal of `feature` (outward on a closed outward mesh); zero
    /// when the feature's faces are all degenerate.
    Eigen::Vector3d normal = Eigen::Vector3d::Zero();
  };

  /// `positions` 3 x #V (m), `triangles` 3 x #T. The schedule shapes the BVH (the instrument's by
  /// default). Throws InputError as Bvh does.
  MeshDistance(const Eigen::Matrix3Xd& positions,
               const Eigen::Matrix3Xi& triangles,
               BvhSchedule schedule = BvhSchedule::instrument());

  /// New vertex positions (3 x #V, same count): refits the tree, O(#V + #T), no allocation;
  /// nothing when they equal the current ones. The pseudonormals are made per query. A rigid
  /// instrument may instead be queried in its own frame (transform the query point), which needs no
  /// update at all.
  void update(const Eigen::Matrix3Xd& positions);

  /// The closest point of the mesh to `point`, its feature, and the sign from the pseudonormal
  /// test (see above). Ties go to the triangle found first. No allocation. `hint`: as for
  /// nearest_within().
  Nearest nearest(const Eigen::Vector3d& point, QueryStats* stats = nullptr, int hint = -1) const;

  /// nearest() among the surface points nearer than `radius` (m) only: none when the surface is
  /// farther. Only the nodes nearer than `radius` are opened, so a point far from the surface
  /// costs a few node tests, not a search for its nearest point.
  /// `hint`: a triangle likely to hold the nearest point (the one an earlier query of a nearby
  /// point found; -1: none). Its distance bounds the descent from the start, so only nodes
  /// nearer than it are opened: a point that moved little since that query costs a few node
  /// tests instead of a search from `radius`. The answer is the same but for ties (equally
  /// near triangles on a shared edge or vertex: the hint wins them).
  std::optional<Nearest> nearest_within(const Eigen::Vector3d& point,
                                        double radius,
                                        QueryStats* stats = nullptr,
                                        int hint = -1) const;

  /// Shorthands for nearest(point).signed_distance and its sign.
  double signed_distance(const Eigen::Vector3d& point) const {
    return nearest(point).signed_distance;
  }
  bool inside(const Eigen::Vector3d& point) const { return signed_distance(point) < 0.0; }

  /// The box of the whole mesh at its current positions (empty for an empty mesh).
  Aabb bounds() const { return tree_.empty() ? Aabb{} : tree_.nodes().front().box; }
  const Bvh& tree() const { return tree_; }
  const Eigen::Matrix3Xd& positions() const { return positions_; }

 private:
  /// The descent behind nearest(): the closest point among those nearer than sqrt(best_squared)
  /// (triangle -1 when there is none), with its side; triangle `hint` (>= 0) is tried first.
  Nearest search(const Eigen::Vector3d& point,
                 double best_squared,
                 QueryStats* stats,
                 int hint = -1) const;
  /// Unit normal of triangle t (zero when it is degenerate).
  Eigen::Vector3d face_normal(int t) const;
  /// Pseudonormal (not normalised) of an edge: its faces' unit normals summed.
  Eigen::Vector3d edge_pseudonormal(int edge) const;
  /// Angle-weighted pseudonormal (not normalised) of a vertex: its corners' angles times their
  /// faces' unit normals.
  Eigen::Vector3d vertex_pseudonormal(int vertex) const;
  /// Angle-weighted pseudonormal (not normalised) of a feature of triangle t.
  Eigen::Vector3d pseudonormal(int t, TriangleFeature feature) const;

  Bvh tree_;
  Eigen::Matrix3Xd positions_;
  Eigen::Matrix3Xi triangles_;
  Eigen::Matrix3Xi triangle_edges_;  ///< 3 x #T: edge index of edge k (vertex k to k + 1)
  /// Per vertex: its corners, triangle * 3 + the corner's index, in triangle order.
  Incidences vertex_corners_;
  /// Per edge: its triangles' sides, triangle * 3 + the side's index, in triangle order.
  Incidences edge_sides_;
};

}  // namespace softbench::collision
