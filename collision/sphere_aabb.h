// SPDX-License-Identifier: MIT
#pragma once

#include "collision/aabb.h"
#include "collision/sphere.h"

#include <Eigen/Core>

#include <cmath>

namespace softbench::collision {

/// The thesis's hybrid volume (section 4.3): the intersection of a sphere and a box, both holding
/// the same content. Overlap tests the sphere first (cheap, rejects well far away) and the box
/// only if the spheres overlap (tighter near contact).
struct SphereAabb {
  Sphere sphere;
  Aabb box;

  bool contains(const Eigen::Vector3d& point) const {
    return sphere.contains(point) && box.contains(point);
  }
};

/// Both volumes fitted to the columns of `points` (3 x #P); the sphere is centred at the box
/// centre (see fit_sphere).
inline SphereAabb fit_sphere_aabb(const Eigen::Matrix3Xd& points) {
  return {fit_sphere(points), fit_aabb(points)};
}

inline SphereAabb merge(const SphereAabb& a, const SphereAabb& b) {
  return {merge(a.sphere, b.sphere), merge(a.box, b.box)};
}

/// Sphere test first, then the box test.
inline bool overlap(const SphereAabb& a, const SphereAabb& b) {
  return overlap(a.sphere, b.sphere) && overlap(a.box, b.box);
}

/// Lower bound on the distance from `point` to the content: the larger of the two volumes'
/// distances, since the content lies in both.
inline double distance(const SphereAabb& volume, const Eigen::Vector3d& point) {
  return std::max(distance(volume.sphere, point), std::sqrt(squared_distance(volume.box, point)));
}

}  // namespace softbench::collision
