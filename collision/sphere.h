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
