// SPDX-License-Identifier: MIT
#include "collision/tri_tri_guigue.h"

#include "collision/tri_tri_coplanar_double.h"

#include <Eigen/Geometry>

#include <array>
#include <utility>

namespace softbench::collision {
namespace {

using Vec3 = Eigen::Vector3d;

/// [a, b, c, d] = (b - a) x (c - a) . (d - a) in double (the paper's orientation determinant,
/// written with the differences it uses).
double orient(const Vec3& a, const Vec3& b, const Vec3& c, const Vec3& d) {
  return (b - a).cross(c - a).dot(d - a);
}

/// Point where edge (from, to) crosses a plane, from the vertices' distances to it.
Vec3 crossing(const Vec3& from, const Vec3& to, double d_from, double d_to) {
  const double denominator = d_from - d_to;
  return denominator != 0.0 ? from + (d_from / denominator) * (to - from) : from;
}

/// The canonical configuration: p1 alone on its side of plane 2 (q1, r1 on the other side or
/// on it), p2 alone on its side of plane 1, both oriented so that the intervals on the line are
/// [i, j] with i on p1q1, j on p1r1 and [k, l] with k on p2q2, l on p2r2 (the paper's
/// CHECK_MIN_MAX): they overlap unless l < i or j < k, two orient3d signs.
struct Canonical {
  std::array<Vec3, 3> t1;    // p1, q1, r1
  std::array<Vec3, 3> t2;    // p2, q2, r2
  std::array<double, 3> d1;  // distances of t1's vertices to plane 2 (in t1's order)
  std::array<double, 3> d2;  // distances of t2's vertices to plane 1
};

TriTriResult check_min_max(const Canonical& c) {
  const Vec3& p1 = c.t1[0];
  const Vec3& q1 = c.t1[1];
  const Vec3& r1 = c.t1[2];
  const Vec3& p2 = c.t2[0];
  const Vec3& q2 = c.t2[1];
  const Vec3& r2 = c.t2[2];
  if (orient(q1, p2, p1, q2) > 0.0) {
    return {};
  }
  if (orient(p1, p2, r1, r2) > 0.0) {
    return {};
  }
  // The segment, after the decision: the interval ends from the plane distances, ordered along
  // the line direction (the overlap of [i, j] and [k, l]).
  const Vec3 i = crossing(p1, q1, c.d1[0], c.d1[1]);
  const Vec3 j = crossing(p1, r1, c.d1[0], c.d1[2]);
  const Vec3 k = crossing(p2, q2, c.d2[0], c.d2[1]);
  const Vec3 l = crossing(p2, r2, c.d2[0], c.d2[2]);
  const Vec3 direction = (q1 - p1).cross(r1 - p1).cross((q2 - p2).cross(r2 - p2));
  auto ordered = [&](const Vec3& x, const Vec3& y) {
    return direction.dot(x) <= direction.dot(y) ? std::pair(x, y) : std::pair(y, x);
  };
  const auto [i_low, i_high] = ordered(i, j);
  const auto [k_low, k_high] = ordered(k, l);
  TriTriResult result;
  result.contact = TriTriContact::kSegment;
  result.a = direction.dot(i_low) >= direction.dot(k_low) ? i_low : k_low;
  result.b = direction.dot(i_high) <= direction.dot(k_high) ? i_high : k_high;
  return result;
}

/// The paper's TRI_TRI_3D: p1 is already alone on its side of plane 2 (positive side); permute
/// triangle 2 so that p2 is alone on its side of plane 1, swapping q2/r2 when p2's side is
/// negative to keep the orientation convention.
TriTriResult tri_tri_3d(const std::array<Vec3, 3>& t1,
                        const std::array<double, 3>& d1,
                        const std::array<Vec3, 3>& t2,
                        const std::array<double, 3>& d2,
                        const Vec3& n1) {
  auto make = [&](std::array<int, 3> o1, std::array<int, 3> o2) {
    Canonical c;
    for (int v = 0; v < 3; ++v) {
      c.t1[v] = t1[o1[v]];
      c.d1[v] = d1[o1[v]];
      c.t2[v] = t2[o2[v]];
      c.d2[v] = d2[o2[v]];
    }
    return check_min_max(c);
  };
  const std::array<int, 3> same = {0, 1, 2};
  const std::array<int, 3> swapped = {0, 2, 1};
  const double dp2 = d2[0];
  const double dq2 = d2[1];
  const double dr2 = d2[2];
  if (dp2 > 0.0) {
    if (dq2 > 0.0) {
      return make(swapped, {2, 0, 1});
    }
    if (dr2 > 0.0) {
      return make(swapped, {1, 2, 0});
    }
    return make(same, {0, 1, 2});
  }
  if (dp2 < 0.0) {
    if (dq2 < 0.0) {
      return make(same, {2, 0, 1});
    }
    if (dr2 < 0.0) {
      return make(same, {1, 2, 0});
    }
    return make(swapped, {0, 1, 2});
  }
  if (dq2 < 0.0) {
    return dr2 >= 0.0 ? make(swapped, {1, 2, 0}) : make(same, {0, 1, 2});
  }
  if (dq2 > 0.0) {
    return dr2 > 0.0 ? make(swapped, {0, 1, 2}) : make(same, {1, 2, 0});
  }
  if (dr2 > 0.0) {
    return make(same, {2, 0, 1});
  }
  if (dr2 < 0.0) {
    return make(swapped, {2, 0, 1});
  }
  TriTriResult result;
  if (detail::coplanar_triangles_meet_double(t1, t2, n1)) {
    result.contact = TriTriContact::kCoplanar;
  }
  return result;
}

}  // namespace

TriTriResult tri_tri_guigue(const Vec3& p1,
                            const Vec3& q1,
                            const Vec3& r1,
                            const Vec3& p2,
                            const Vec3& q2,
                            const Vec3& r2) {
  // Triangle 1 against plane 2: orient3d(p2, q2, r2, x).
  const Vec3 n2 = (q2 - p2).cross(r2 - p2);
  const std::array<double, 3> d1 = {n2.dot(p1 - p2), n2.dot(q1 - p2), n2.dot(r1 - p2)};
  if (d1[0] * d1[1] > 0.0 && d1[0] * d1[2] > 0.0) {
    return {};
  }
  const Vec3 n1 = (q1 - p1).cross(r1 - p1);
  const std::array<double, 3> d2 = {n1.dot(p2 - p1), n1.dot(q2 - p1), n1.dot(r2 - p1)};
  if (d2[0] * d2[1] > 0.0 && d2[0] * d2[2] > 0.0) {
    return {};
  }
  const std::array<Vec3, 3> t1 = {p1, q1, r1};
  const std::array<Vec3, 3> t2 = {p2, q2, r2};
  // Circular permutation of triangle 1 so that p1 is alone on its side; when that side is the
  // negative one, triangle 2's q2 and r2 swap (the orientation flips).
  auto run = [&](std::array<int, 3> o1, bool negative) {
    std::array<Vec3, 3> a;
    std::array<double, 3> da;
    for (int v = 0; v < 3; ++v) {
      a[v] = t1[o1[v]];
      da[v] = d1[o1[v]];
    }
    if (!negative) {
      return tri_tri_3d(a, da, t2, d2, n1);
    }
    return tri_tri_3d(a, da, {t2[0], t2[2], t2[1]}, {d2[0], d2[2], d2[1]}, n1);
  };
  const double dp1 = d1[0];
  const double dq1 = d1[1];
  const double dr1 = d1[2];
  if (dp1 > 0.0) {
    if (dq1 > 0.0) {
      return run({2, 0, 1}, true);
    }
    if (dr1 > 0.0) {
      return run({1, 2, 0}, true);
    }
    return run({0, 1, 2}, false);
  }
  if (dp1 < 0.0) {
    if (dq1 < 0.0) {
      return run({2, 0, 1}, false);
    }
    if (dr1 < 0.0) {
      return run({1, 2, 0}, false);
    }
    return run({0, 1, 2}, true);
  }
  if (dq1 < 0.0) {
    return dr1 >= 0.0 ? run({1, 2, 0}, true) : run({0, 1, 2}, false);
  }
  if (dq1 > 0.0) {
    return dr1 > 0.0 ? run({0, 1, 2}, true) : run({1, 2, 0}, false);
  }
  if (dr1 > 0.0) {
    return run({2, 0, 1}, false);
  }
  if (dr1 < 0.0) {
    return run({2, 0, 1}, true);
  }
  TriTriResult result;
  if (detail::coplanar_triangles_meet_double(t1, t2, n1)) {
    result.contact = TriTriContact::kCoplanar;
  }
  return result;
}

}  // namespace softbench::collision
