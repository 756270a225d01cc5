// SPDX-License-Identifier: MIT
#pragma once

#include "collision/aabb.h"
#include "collision/sphere.h"

#include <Eigen/Core>

#include <algorithm>
#include <cmath>
#include <limits>

namespace softbench::collision {

/// The box's circumsphere: centred at the box centre, radius half the diagonal (padded). It holds
/// the box and so everything in it. A BVH node whose box is tested too uses it as its sphere
/// (see bvh.h), formed on demand rather than stored.
inline Sphere circumsphere(const Aabb& box) {
  const Eigen::Vector3d center = box.center();
  return {center, padded_radius(0.5 * std::sqrt(box.extent().squaredNorm()), center)};
}

/// The largest coordinate magnitude in the box: the `magnitude` circumspheres_overlap needs.
inline double coordinate_magnitude(const Aabb& box) {
  return std::max(box.min.cwiseAbs().maxCoeff(), box.max.cwiseAbs().maxCoeff());
}

/// Closed overlap of the two boxes' circumspheres without forming them: no square root, no
/// centre, nothing stored, so a tree whose spheres are circumspheres refits exactly as an AABB
/// tree does. `magnitude` bounds every coordinate of both boxes (coordinate_magnitude of any box
/// holding both, e.g. the roots of the trees they belong to).
///
/// With s = min + max and e = max - min per box, the spheres overlap iff
/// |s_a - s_b| <= |e_a| + |e_b|, i.e. iff L = |s_a - s_b|^2 - |e_a|^2 - |e_b|^2 <= 0 or
/// L^2 <= 4 |e_a|^2 |e_b|^2. Evaluated plainly first: an "overlap" from it is returned as is
/// (a wrong one only costs the box test that follows), so only a "miss" is re-checked with
/// round-off bounds, which keeps the common case (spheres that overlap) cheap.
/// Conservative: true whenever the exact circumspheres overlap, including touching.
inline bool circumspheres_overlap(const Aabb& a, const Aabb& b, double magnitude) {
  double separation[3], gap_squared = 0.0, extent_a = 0.0, extent_b = 0.0;
  for (int k = 0; k < 3; ++k) {
    separation[k] = std::abs((a.min[k] + a.max[k]) - (b.min[k] + b.max[k]));
    gap_squared += separation[k] * separation[k];
    const double ea = a.max[k] - a.min[k], eb = b.max[k] - b.min[k];
    extent_a += ea * ea;
    extent_b += eb * eb;
  }
  const double excess = gap_squared - extent_a - extent_b;
  if (excess <= 0.0 || excess * excess <= 4.0 * extent_a * extent_b) {
    return true;
  }
  // A miss, re-checked. Each separation is off by at most 8 u magnitude (u = 2^-53), so it is
  // shrunk by more than that; every later quantity is a sum or product of non-negative terms
  // whose relative error (a few u) the 1e-14 factors cover, so the excess and its square stay
  // lower bounds and the right-hand side an upper bound. Overflow only answers true.
  constexpr double kSlack = 1e-14;
  const double shrink = 2e-15 * magnitude;
  double lower_squared = 0.0;
  for (const double d : separation) {
    const double lower = std::max(d - shrink, 0.0);
    lower_squared += lower * lower;
  }
  const double lower_excess =
      lower_squared * (1.0 - kSlack) - (extent_a + extent_b) * (1.0 + kSlack);
  return !(lower_excess > 0.0
           && lower_excess * lower_excess > 4.0 * extent_a * extent_b * (1.0 + kSlack));
}

}  // namespace softbench::collision
