// SPDX-License-Identifier: MIT
#include "collision/bvh.h"

#include "geometry/input_error.h"

#include <algorithm>
#include <cmath>
#include <sstream>
#include <string>

namespace softbench::collision {
namespace {

void validate(const Eigen::Matrix3Xd& positions,
              const Eigen::Matrix3Xi& triangles,
              const BvhSchedule& schedule) {
  if (schedule.levels.empty() || schedule.max_levels() > BvhSchedule::kMaxLevels) {
    throw InputError("BVH schedule: expected 1 to " + std::to_string(BvhSchedule::kMaxLevels)
                     + " levels, got " + std::to_string(schedule.max_levels()));
  }
  if (schedule.max_leaf_triangles < 1) {
    throw InputError("BVH schedule: expected max_leaf_triangles >= 1, got "
                     + std::to_string(schedule.max_leaf_triangles));
  }
  if (!positions.allFinite()) {
    throw InputError("BVH: positions contain NaN or infinity");
  }
  for (Eigen::Index t = 0; t < triangles.cols(); ++t) {
    for (int k = 0; k < 3; ++k) {
      const int v = triangles(k, t);
      if (v < 0 || v >= positions.cols()) {
        std::ostringstream message;
        message << "BVH: triangle " << t << " has vertex index " << v << ", expected 0.."
                << positions.cols() - 1;
        throw InputError(message.str());
      }
    }
  }
}

struct Builder {
  const Eigen::Matrix3Xi& triangles;
  const BvhSchedule& schedule;
  Eigen::Matrix3Xd centroids;
  std::vector<int>& slots;  // slot -> triangle, permuted in place by the splits
  std::vector<BvhNode>& nodes;

  void split(int node_index, int first, int count, int level) {
    nodes[static_cast<std::size_t>(node_index)].level = static_cast<std::uint8_t>(level);
    nodes[static_cast<std::size_t>(node_index)].kind = schedule.kind_at(level);
    nodes[static_cast<std::size_t>(node_index)].box_tested = schedule.tests_box(level);
    if (count <= schedule.max_leaf_triangles || level + 1 >= schedule.max_levels()) {
      nodes[static_cast<std::size_t>(node_index)].first = first;
      nodes[static_cast<std::size_t>(node_index)].count = count;
      return;
    }
    Aabb bounds;
    for (int s = first; s < first + count; ++s) {
      bounds.extend(Eigen::Vector3d(centroids.col(slots[static_cast<std::size_t>(s)])));
    }
    int axis = 0;
    bounds.extent().maxCoeff(&axis);
    const auto begin = slots.begin() + first;
    const int half = count / 2;
    // Ties broken by triangle index, so the build is deterministic whatever nth_element does.
    std::nth_element(begin, begin + half, begin + count, [&](int a, int b) {
      const double ca = centroids(axis, a), cb = centroids(axis, b);
      return ca < cb || (ca == cb && a < b);
    });
    const int left = static_cast<int>(nodes.size());
    nodes.emplace_back();
    nodes.emplace_back();
    nodes[static_cast<std::size_t>(node_index)].first = left;
    nodes[static_cast<std::size_t>(node_index)].count = 0;
    split(left, first, half, level + 1);
    split(left + 1, first + half, count - half, level + 1);
  }
};

}  // namespace

Bvh::Bvh(const Eigen::Matrix3Xd& positions, const Eigen::Matrix3Xi& triangles, BvhSchedule schedule)
    : schedule_(std::move(schedule)), num_vertices_(static_cast<int>(positions.cols())) {
  validate(positions, triangles, schedule_);
  const int num_triangles = static_cast<int>(triangles.cols());
  if (num_triangles == 0) {
    return;
  }
  slot_triangle_.resize(static_cast<std::size_t>(num_triangles));
  for (int t = 0; t < num_triangles; ++t) {
    slot_triangle_[static_cast<std::size_t>(t)] = t;
  }
  Builder builder{triangles, schedule_, Eigen::Matrix3Xd(3, num_triangles), slot_triangle_, nodes_};
  for (int t = 0; t < num_triangles; ++t) {
    builder.centroids.col(t) = (positions.col(triangles(0, t)) + positions.col(triangles(1, t))
                                + positions.col(triangles(2, t)))
                               / 3.0;
  }
  nodes_.reserve(static_cast<std::size_t>(2 * num_triangles));
  nodes_.emplace_back();
  builder.split(0, 0, num_triangles, 0);
  nodes_.shrink_to_fit();

  slot_vertices_.resize(3, num_triangles);
  for (int s = 0; s < num_triangles; ++s) {
    slot_vertices_.col(s) = triangles.col(slot_triangle_[static_cast<std::size_t>(s)]);
  }
  std::vector<int> unique;
  for (BvhNode& node : nodes_) {
    info_.levels = std::max(info_.levels, node.level + 1);
    if (!node.is_leaf()) {
      continue;
    }
    ++info_.leaves;
    info_.max_leaf_triangles = std::max(info_.max_leaf_triangles, node.count);
    if (node.count > schedule_.max_leaf_triangles) {
      ++info_.oversize_leaves;
    }
    unique.clear();
    for (int s = node.first; s < node.first + node.count; ++s) {
      for (int k = 0; k < 3; ++k) {
        unique.push_back(slot_vertices_(k, s));
      }
    }
    std::sort(unique.begin(), unique.end());
    unique.erase(std::unique(unique.begin(), unique.end()), unique.end());
    node.vertex_first = static_cast<int>(leaf_vertices_.size());
    node.vertex_count = static_cast<int>(unique.size());
    leaf_vertices_.insert(leaf_vertices_.end(), unique.begin(), unique.end());
  }
  refit(positions);
}

void Bvh::refit(const Eigen::Matrix3Xd& positions) {
  if (positions.cols() != num_vertices_) {
    throw InputError("BVH refit: expected " + std::to_string(num_vertices_)
                     + " vertex positions, got " + std::to_string(positions.cols()));
  }
  for (auto node = nodes_.rbegin(); node != nodes_.rend(); ++node) {
    if (node->is_leaf()) {
      const int* vertex = leaf_vertices_.data() + node->vertex_first;
      const int* const end = vertex + node->vertex_count;
      double lo[3] = {positions(0, *vertex), positions(1, *vertex), positions(2, *vertex)};
      double hi[3] = {lo[0], lo[1], lo[2]};
      for (const int* v = vertex + 1; v != end; ++v) {
        for (int k = 0; k < 3; ++k) {
          lo[k] = std::min(lo[k], positions(k, *v));
          hi[k] = std::max(hi[k], positions(k, *v));
        }
      }
      node->box.min = Eigen::Vector3d(lo[0], lo[1], lo[2]);
      node->box.max = Eigen::Vector3d(hi[0], hi[1], hi[2]);
    } else {
      const BvhNode& left = nodes_[static_cast<std::size_t>(node->first)];
      const BvhNode& right = nodes_[static_cast<std::size_t>(node->first) + 1];
      node->box.min = left.box.min.cwiseMin(right.box.min);
      node->box.max = left.box.max.cwiseMax(right.box.max);
    }
    if (!node->has_sphere() || node->has_box()) {
      continue;  // no sphere, or the box's circumsphere, formed by the query (see bvh.h)
    }
    const Eigen::Vector3d center = node->box.center();
    // Squared reaches, so that a bound without a sphere costs no square root.
    double radius_squared = 0.0;
    if (node->is_leaf()) {
      for (const int v : leaf_vertices(*node)) {
        radius_squared = std::max(radius_squared, (positions.col(v) - center).squaredNorm());
      }
    } else {
      for (const int child_index : {node->first, node->first + 1}) {
        const BvhNode& child = nodes_[static_cast<std::size_t>(child_index)];
        double reach_squared = farthest_squared_distance(child.box, center);
        if (child.has_sphere()) {
          const Sphere sphere = child.sphere_of();  // a box-tested child stores none
          const double reach = (sphere.center - center).norm() + sphere.radius;
          reach_squared = std::min(reach_squared, reach * reach);
        }
        radius_squared = std::max(radius_squared, reach_squared);
      }
    }
    node->sphere.center = center;
    node->sphere.radius = padded_radius(std::sqrt(radius_squared), center);
  }
  if (!nodes_.empty()) {
    coordinate_magnitude_ = collision::coordinate_magnitude(nodes_.front().box);
  }
}

}  // namespace softbench::collision
