// SPDX-License-Identifier: MIT
#pragma once

#include "collision/aabb.h"

#include <Eigen/Core>

#include <algorithm>
#include <cmath>

namespace softbench::collision {

/// Bounding sphere, closed (touching spheres overlap). Radii are computed with square roots and
/// so carry round-off; every function that makes a sphere pads the radius by kSpherePadding
/// (relative to the radius plus the centre's magnitude) so that containment and the overlap
/// tests stay conservative: a sphere never misses a point it was fitted to. A negative radius
/// means empty.
struct Sphere {
  Eigen::Vector3d center = Eigen::Vector3d::Zero();
  double radius = -1.0;

  bool empty() const { return radius < 0.0; }
  /// Closed containment with the padding already in the radius: exact comparison.
  bool contains(const Eigen::Vector3d& point) const {
    return (point - center).squaredNorm() <= radius * radius;
  }
};

/// Relative padding of sphere radii: a few hundred ulps, far above the round-off of a sqrt and
/// a squared norm, far below anything that changes which nodes a query visits.
inline constexpr double kSpherePadding = 1e-13;

/// Pads `radius` for a sphere at `center` (see Sphere).
inline double padded_radius(double radius, const Eigen::Vector3d& center) {
  return radius + kSpherePadding * (radius + center.cwiseAbs().maxCoeff());
}

/// A sphere holding every column of `points` (3 x #P): centred at the points' bounding-box centre
/// with the smallest radius for that centre. Not the minimal sphere (Welzl), but never larger
/// than the box's half-diagonal, one pass, and the same rule the BVH refit uses.
inline Sphere fit_sphere(const Eigen::Matrix3Xd& points) {
  Sphere sphere;
  if (points.cols() == 0) {
    return sphere;
  }
  sphere.center = fit_aabb(points).center();
  double max_squared = 0.0;
  for (Eigen::Index i = 0; i < points.cols(); ++i) {
    max_squared = std::max(max_squared, (points.col(i) - sphere.center).squaredNorm());
  }
  sphere.radius = padded_radius(std::sqrt(max_squared), sphere.center);
  return sphere;
}

/// The smallest sphere holding both spheres (exact construction, padded).
inline Sphere merge(const Sphere& a, const Sphere& b) {
  if (a.empty()) {
    return b;
  }
  if (b.empty()) {
    return a;
  }
  const Eigen::Vector3d offset = b.center - a.center;
  const double distance = offset.norm();
  if (distance + b.radius <= a.radius) {
    return a;
  }
  if (distance + a.radius <= b.radius) {
    return b;
  }
  Sphere sphere;
  const double radius = 0.5 * (distance + a.radius + b.radius);
  // distance > 0 here: equal centres fall into one of the containment cases above.
  sphere.center = a.center + offset * ((radius - a.radius) / distance);
  sphere.radius = padded_radius(radius, sphere.center);
  return sphere;
}

/// Closed overlap of two spheres.
inline bool overlap(const Sphere& a, const Sphere& b) {
  const double reach = a.radius + b.radius;
  return (a.center - b.center).squaredNorm() <= reach * reach;
}

/// Closed overlap of a sphere and a box: the box's closest point to the centre is in the sphere.
inline bool overlap(const Sphere& sphere, const Aabb& box) {
  return squared_distance(box, sphere.center) <= sphere.radius * sphere.radius;
}
inline bool overlap(const Aabb& box, const Sphere& sphere) {
  return overlap(sphere, box);
}

/// Distance from `point` to the sphere's solid (0 inside), m: a lower bound on the distance to
/// anything the sphere holds.
inline double distance(const Sphere& sphere, const Eigen::Vector3d& point) {
  return std::max(0.0, (point - sphere.center).norm() - sphere.radius);
}

}  // namespace softbench::collision
