// SPDX-License-Identifier: MIT
#include "collision/mesh_distance.h"

#include <Eigen/Geometry>

#include <algorithm>
#include <array>
#include <cmath>
#include <map>
#include <optional>
#include <span>
#include <utility>

namespace softbench::collision {
namespace {

// Squared lower bound on the distance from `point` to anything the node holds.
double squared_lower_bound(const BvhNode& node, const Eigen::Vector3d& point) {
  if (node.has_box()) {
    return squared_distance(node.box, point);  // the box lies inside any sphere it is tested with
  }
  if (!node.has_sphere()) {
    return 0.0;
  }
  const double gap = distance(node.sphere, point);
  return gap * gap;
}

// Angle at vertex `a` of triangle (a, b, c), radians (0 for a zero-length edge).
double corner_angle(const Eigen::Vector3d& a, const Eigen::Vector3d& b, const Eigen::Vector3d& c) {
  const Eigen::Vector3d u = b - a, v = c - a;
  // atan2 of |u x v| and u . v stays accurate near 0 and pi, unlike acos.
  return std::atan2(u.cross(v).norm(), u.dot(v));
}

}  // namespace

MeshDistance::MeshDistance(const Eigen::Matrix3Xd& positions,
                           const Eigen::Matrix3Xi& triangles,
                           BvhSchedule schedule)
    : tree_(positions, triangles, std::move(schedule)),
      positions_(positions),
      triangles_(triangles),
      triangle_edges_(3, triangles.cols()) {
  std::map<std::pair<int, int>, int> edge_index;
  for (Eigen::Index t = 0; t < triangles.cols(); ++t) {
    for (int k = 0; k < 3; ++k) {
      const auto key = std::minmax(triangles(k, t), triangles((k + 1) % 3, t));
      const auto [it, inserted] = edge_index.try_emplace(key, static_cast<int>(edge_index.size()));
      triangle_edges_(k, t) = it->second;
    }
  }
  // Each vertex's corners (triangle * 3 + k) and each edge's triangles, in triangle order: a
  // pseudonormal sums its faces' normals in that order.
  // Column-major: entry 3 t + k is corner k of triangle t, and its side from corner k.
  vertex_corners_ = group_by_owner(
      std::span<const int>(triangles.data(), static_cast<std::size_t>(triangles.size())),
      static_cast<int>(positions.cols()));
  edge_sides_ =
      group_by_owner(std::span<const int>(triangle_edges_.data(),
                                          static_cast<std::size_t>(triangle_edges_.size())),
                     static_cast<int>(edge_index.size()));
}

void MeshDistance::update(const Eigen::Matrix3Xd& positions) {
  // The harness measures penetration after a step and resolves the next step's contact from the
  // same positions: comparing is O(#V) reads, refit and pseudonormals several times that.
  if (positions.cols() == positions_.cols() && positions == positions_) {
    return;
  }
  tree_.refit(positions);  // checks the vertex count
  positions_ = positions;
}

// Every normal is made when a query's nearest feature needs it, not at update(): a query
// needs one, an update would make one per triangle, and a contact step updates the tissue
// several times for a few hundred queries near the instrument.
Eigen::Vector3d MeshDistance::face_normal(int t) const {
  const Eigen::Vector3d a = positions_.col(triangles_(0, t)), b = positions_.col(triangles_(1, t)),
                        c = positions_.col(triangles_(2, t));
  const Eigen::Vector3d normal = (b - a).cross(c - a);
  const double length = normal.norm();
  return length > 0.0 ? Eigen::Vector3d(normal / length) : Eigen::Vector3d::Zero();
}

Eigen::Vector3d MeshDistance::edge_pseudonormal(int edge) const {
  Eigen::Vector3d sum = Eigen::Vector3d::Zero();
  for (int k = edge_sides_.offsets[static_cast<std::size_t>(edge)];
       k < edge_sides_.offsets[static_cast<std::size_t>(edge) + 1]; ++k) {
    sum += face_normal(edge_sides_.items[static_cast<std::size_t>(k)] / 3);
  }
  return sum;
}

Eigen::Vector3d MeshDistance::vertex_pseudonormal(int vertex) const {
  Eigen::Vector3d sum = Eigen::Vector3d::Zero();
  for (int k = vertex_corners_.offsets[static_cast<std::size_t>(vertex)];
       k < vertex_corners_.offsets[static_cast<std::size_t>(vertex) + 1]; ++k) {
    const int corner = vertex_corners_.items[static_cast<std::size_t>(k)];
    const int t = corner / 3;
    const int at = corner % 3;
    const Eigen::Vector3d corners[3] = {positions_.col(triangles_(0, t)),
                                        positions_.col(triangles_(1, t)),
                                        positions_.col(triangles_(2, t))};
    sum += corner_angle(corners[at], corners[(at + 1) % 3], corners[(at + 2) % 3]) * face_normal(t);
  }
  return sum;
}

MeshDistance::Nearest MeshDistance::nearest(const Eigen::Vector3d& point,
                                            QueryStats* stats,
                                            int hint) const {
  return search(point, std::numeric_limits<double>::infinity(), stats, hint);
}

std::optional<MeshDistance::Nearest> MeshDistance::nearest_within(const Eigen::Vector3d& point,
                                                                  double radius,
                                                                  QueryStats* stats,
                                                                  int hint) const {
  Nearest found = search(point, radius * radius, stats, hint);
  return found.triangle >= 0 ? std::optional<Nearest>(found) : std::nullopt;
}

MeshDistance::Nearest MeshDistance::search(const Eigen::Vector3d& point,
                                           double best_squared,
                                           QueryStats* stats,
                                           int hint) const {
  Nearest best;
  QueryStats counts;
  if (tree_.empty()) {
    return best;
  }
  // Triangle `triangle` with corners a, b, c becomes the best if it is nearer.
  const auto consider = [&](int triangle, const auto& a, const auto& b, const auto& c) {
    const TrianglePoint candidate = closest_point_on_triangle(point, a, b, c);
    ++counts.tri_tests;
    const double squared = (candidate.point - point).squaredNorm();
    if (squared < best_squared) {
      best_squared = squared;
      best.triangle = triangle;
      best.point = candidate.point;
      best.barycentric = candidate.barycentric;
      best.feature = candidate.feature;
    }
  };
  if (hint >= 0) {
    consider(hint, positions_.col(triangles_(0, hint)), positions_.col(triangles_(1, hint)),
             positions_.col(triangles_(2, hint)));
  }
  // Depth-first, each pop pushes at most two: the stack holds at most levels + 1 entries. Left
  // uninitialised (a std::pair would zero all of them each query).
  struct Pending {
    int node;
    double bound;
  };
  std::array<Pending, BvhSchedule::kMaxLevels + 2> stack;
  int top = 0;
  const std::vector<BvhNode>& nodes = tree_.nodes();
  stack[static_cast<std::size_t>(top++)] = {0, squared_lower_bound(nodes[0], point)};
  while (top > 0) {
    const auto [index, bound] = stack[static_cast<std::size_t>(--top)];
    if (bound >= best_squared) {
      continue;
    }
    const BvhNode& node = nodes[static_cast<std::size_t>(index)];
    ++counts.node_visits;
    if (node.is_leaf()) {
      ++counts.leaf_visits;
      for (int slot = node.first; slot < node.first + node.count; ++slot) {
        const auto tri = tree_.slot_vertices().col(slot);
        const auto a = positions_.col(tri(0)), b = positions_.col(tri(1)),
                   c = positions_.col(tri(2));
        // The triangle's box first: a leaf's triangles are mostly farther than the best found
        // (its box is near, they are not), and the box says so at a fraction of the cost.
        if (squared_distance(Aabb{a.cwiseMin(b).cwiseMin(c), a.cwiseMax(b).cwiseMax(c)}, point)
            >= best_squared) {
          continue;
        }
        consider(tree_.slot_triangle(slot), a, b, c);
      }
      continue;
    }
    const int left = node.first, right = node.first + 1;
    const double left_bound = squared_lower_bound(nodes[static_cast<std::size_t>(left)], point);
    const double right_bound = squared_lower_bound(nodes[static_cast<std::size_t>(right)], point);
    // Push the farther child first so the nearer one is searched first and tightens the bound.
    if (left_bound <= right_bound) {
      stack[static_cast<std::size_t>(top++)] = {right, right_bound};
      stack[static_cast<std::size_t>(top++)] = {left, left_bound};
    } else {
      stack[static_cast<std::size_t>(top++)] = {left, left_bound};
      stack[static_cast<std::size_t>(top++)] = {right, right_bound};
    }
  }
  if (stats != nullptr) {
    counts.pairs_found = best.triangle >= 0 ? 1 : 0;
    *stats = counts;
  }
  if (best.triangle < 0) {
    return best;  // nothing nearer than the bound it started with
  }
  best.distance = std::sqrt(best_squared);
  const Eigen::Vector3d normal = pseudonormal(best.triangle, best.feature);
  const double length = normal.norm();
  best.normal = length > 0.0 ? Eigen::Vector3d(normal / length) : Eigen::Vector3d::Zero();
  // Points on the surface (distance 0) and features without a normal count as outside.
  best.signed_distance = (point - best.point).dot(normal) < 0.0 ? -best.distance : best.distance;
  return best;
}

Eigen::Vector3d MeshDistance::pseudonormal(int t, TriangleFeature feature) const {
  switch (feature) {
    case TriangleFeature::kFace:
      return face_normal(t);
    case TriangleFeature::kEdge01:
      return edge_pseudonormal(triangle_edges_(0, t));
    case TriangleFeature::kEdge12:
      return edge_pseudonormal(triangle_edges_(1, t));
    case TriangleFeature::kEdge20:
      return edge_pseudonormal(triangle_edges_(2, t));
    case TriangleFeature::kVertex0:
      return vertex_pseudonormal(triangles_(0, t));
    case TriangleFeature::kVertex1:
      return vertex_pseudonormal(triangles_(1, t));
    case TriangleFeature::kVertex2:
      return vertex_pseudonormal(triangles_(2, t));
  }
  return Eigen::Vector3d::Zero();
}

}  // namespace softbench::collision
