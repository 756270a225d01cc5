// SPDX-License-Identifier: MIT
#pragma once

#include <Eigen/Core>

#include <algorithm>
#include <cmath>
#include <limits>

namespace softbench::collision {

/// Axis-aligned bounding box, closed: a point on the boundary is inside, and two boxes that only
/// touch overlap. Built from coordinates by min/max only, so containment is exact (no round-off).
/// An empty box has min = +inf, max = -inf and overlaps nothing.
struct Aabb {
  Eigen::Vector3d min = Eigen::Vector3d::Constant(std::numeric_limits<double>::infinity());
  Eigen::Vector3d max = Eigen::Vector3d::Constant(-std::numeric_limits<double>::infinity());

  bool empty() const { return (min.array() > max.array()).any(); }
  Eigen::Vector3d center() const { return 0.5 * (min + max); }
  Eigen::Vector3d extent() const { return max - min; }

  void extend(const Eigen::Vector3d& point) {
    min = min.cwiseMin(point);
    max = max.cwiseMax(point);
  }
  void extend(const Aabb& box) {
    min = min.cwiseMin(box.min);
    max = max.cwiseMax(box.max);
  }
  bool contains(const Eigen::Vector3d& point) const {
    return (point.array() >= min.array()).all() && (point.array() <= max.array()).all();
  }
  bool contains(const Aabb& box) const {
    return (box.min.array() >= min.array()).all() && (box.max.array() <= max.array()).all();
  }
};

/// The smallest box holding every column of `points` (3 x #P); empty for no points.
inline Aabb fit_aabb(const Eigen::Matrix3Xd& points) {
  Aabb box;
  for (Eigen::Index i = 0; i < points.cols(); ++i) {
    box.extend(Eigen::Vector3d(points.col(i)));
  }
  return box;
}

/// The smallest box holding both.
inline Aabb merge(const Aabb& a, const Aabb& b) {
  Aabb box = a;
  box.extend(b);
  return box;
}

/// Closed overlap: touching boxes overlap. Written as six scalar comparisons (no Eigen
/// temporaries) because it is the innermost test of the tree-vs-tree descent.
inline bool overlap(const Aabb& a, const Aabb& b) {
  return a.min.x() <= b.max.x() && b.min.x() <= a.max.x() && a.min.y() <= b.max.y()
         && b.min.y() <= a.max.y() && a.min.z() <= b.max.z() && b.min.z() <= a.max.z();
}

/// Squared Euclidean distance from `point` to the box (0 inside), m^2.
inline double squared_distance(const Aabb& box, const Eigen::Vector3d& point) {
  double sum = 0.0;
  for (int k = 0; k < 3; ++k) {
    const double below = box.min[k] - point[k];
    const double above = point[k] - box.max[k];
    const double d = std::max({below, above, 0.0});
    sum += d * d;
  }
  return sum;
}

/// Squared distance from `center` to the farthest point of the box: the squared radius a sphere
/// at `center` needs to hold the box.
inline double farthest_squared_distance(const Aabb& box, const Eigen::Vector3d& center) {
  double sum = 0.0;
  for (int k = 0; k < 3; ++k) {
    const double far = std::max(std::abs(box.min[k] - center[k]), std::abs(box.max[k] - center[k]));
    sum += far * far;
  }
  return sum;
}

}  // namespace softbench::collision
