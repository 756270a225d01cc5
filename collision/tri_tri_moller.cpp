// SPDX-License-Identifier: MIT
#include "collision/tri_tri_moller.h"

#include "collision/tri_tri_coplanar_double.h"

#include <Eigen/Geometry>

#include <array>
#include <cmath>
#include <utility>

namespace softbench::collision {
namespace {

using Vec3 = Eigen::Vector3d;

/// One triangle's interval on L: parameters (projection on L's dominant axis) and 3D points.
struct Interval {
  double t0 = 0.0;
  double t1 = 0.0;
  Vec3 x0;
  Vec3 x1;
};

/// The paper's ISECT: vertex 0 alone on its side; the interval runs from the crossing of edge
/// 0-1 to that of edge 0-2 (ratios d0 / (d0 - d1)).
Interval isect(const std::array<const Vec3*, 3>& v,
               const std::array<double, 3>& projection,
               const std::array<double, 3>& d) {
  const double r1 = d[0] / (d[0] - d[1]);
  const double r2 = d[0] / (d[0] - d[2]);
  Interval interval;
  interval.t0 = projection[0] + (projection[1] - projection[0]) * r1;
  interval.t1 = projection[0] + (projection[2] - projection[0]) * r2;
  interval.x0 = *v[0] + r1 * (*v[1] - *v[0]);
  interval.x1 = *v[0] + r2 * (*v[2] - *v[0]);
  if (interval.t0 > interval.t1) {
    std::swap(interval.t0, interval.t1);
    std::swap(interval.x0, interval.x1);
  }
  return interval;
}

/// The paper's COMPUTE_INTERVALS: picks the vertex alone on its side; false when all distances
/// are zero (coplanar).
bool compute_interval(const std::array<const Vec3*, 3>& v,
                      const std::array<double, 3>& p,
                      const std::array<double, 3>& d,
                      Interval& out) {
  auto with_first = [&](int k) {
    const int a = (k + 1) % 3;
    const int b = (k + 2) % 3;
    out = isect({v[k], v[a], v[b]}, {p[k], p[a], p[b]}, {d[k], d[a], d[b]});
    return true;
  };
  if (d[0] * d[1] > 0.0) {
    return with_first(2);
  }
  if (d[0] * d[2] > 0.0) {
    return with_first(1);
  }
  if (d[1] * d[2] > 0.0 || d[0] != 0.0) {
    return with_first(0);
  }
  if (d[1] != 0.0) {
    return with_first(1);
  }
  if (d[2] != 0.0) {
    return with_first(2);
  }
  return false;
}

}  // namespace

TriTriResult tri_tri_moller(const Vec3& p0,
                            const Vec3& p1,
                            const Vec3& p2,
                            const Vec3& q0,
                            const Vec3& q1,
                            const Vec3& q2) {
  // Plane of A; signed distances (times |N1|) of B's vertices.
  const Vec3 n1 = (p1 - p0).cross(p2 - p0);
  const double d1 = -n1.dot(p0);
  const std::array<double, 3> du = {n1.dot(q0) + d1, n1.dot(q1) + d1, n1.dot(q2) + d1};
  if (du[0] * du[1] > 0.0 && du[0] * du[2] > 0.0) {
    return {};
  }
  const Vec3 n2 = (q1 - q0).cross(q2 - q0);
  const double d2 = -n2.dot(q0);
  const std::array<double, 3> dv = {n2.dot(p0) + d2, n2.dot(p1) + d2, n2.dot(p2) + d2};
  if (dv[0] * dv[1] > 0.0 && dv[0] * dv[2] > 0.0) {
    return {};
  }
  // Direction of the intersection line; project on its largest component (the paper's shortcut
  // for D . V, which orders points the same way).
  const Vec3 direction = n1.cross(n2);
  const Vec3 magnitude = direction.cwiseAbs();
  const int axis = magnitude.x() > magnitude.y() ? (magnitude.x() > magnitude.z() ? 0 : 2)
                                                 : (magnitude.y() > magnitude.z() ? 1 : 2);
  const std::array<const Vec3*, 3> a = {&p0, &p1, &p2};
  const std::array<const Vec3*, 3> b = {&q0, &q1, &q2};
  Interval ia;
  Interval ib;
  if (!compute_interval(a, {p0[axis], p1[axis], p2[axis]}, dv, ia)
      || !compute_interval(b, {q0[axis], q1[axis], q2[axis]}, du, ib)) {
    TriTriResult result;
    if (detail::coplanar_triangles_meet_double({p0, p1, p2}, {q0, q1, q2}, n1)) {
      result.contact = TriTriContact::kCoplanar;
    }
    return result;
  }
  if (ia.t1 < ib.t0 || ib.t1 < ia.t0) {
    return {};
  }
  TriTriResult result;
  result.contact = TriTriContact::kSegment;
  result.a = ia.t0 >= ib.t0 ? ia.x0 : ib.x0;
  result.b = ia.t1 <= ib.t1 ? ia.x1 : ib.x1;
  return result;
}

}  // namespace softbench::collision
