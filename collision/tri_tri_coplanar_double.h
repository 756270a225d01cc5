// SPDX-License-Identifier: MIT
#pragma once

// Plain-double coplanar triangle test shared by the peers (Moeller, Guigue-Devillers): project on
// the coordinate plane that drops the dominant axis of the normal, then edge-edge crossings and
// vertex containment with orient2d evaluated in double (closed sets: zero counts as touching).
// Internal to collision/tri_tri_*.cpp.

#include <Eigen/Core>

#include <array>
#include <cmath>

namespace softbench::collision::detail {

inline double orient2d_double(const Eigen::Vector2d& a,
                              const Eigen::Vector2d& b,
                              const Eigen::Vector2d& c) {
  return (b.x() - a.x()) * (c.y() - a.y()) - (b.y() - a.y()) * (c.x() - a.x());
}

inline bool segments_meet_2d(const Eigen::Vector2d& a0,
                             const Eigen::Vector2d& a1,
                             const Eigen::Vector2d& b0,
                             const Eigen::Vector2d& b1) {
  const double o0 = orient2d_double(a0, a1, b0);
  const double o1 = orient2d_double(a0, a1, b1);
  const double o2 = orient2d_double(b0, b1, a0);
  const double o3 = orient2d_double(b0, b1, a1);
  if (o0 == 0.0 && o1 == 0.0) {  // collinear: overlapping boxes
    for (int k = 0; k < 2; ++k) {
      if (std::max(a0[k], a1[k]) < std::min(b0[k], b1[k])
          || std::max(b0[k], b1[k]) < std::min(a0[k], a1[k])) {
        return false;
      }
    }
    return true;
  }
  return o0 * o1 <= 0.0 && o2 * o3 <= 0.0;
}

inline bool point_in_triangle_2d(const std::array<Eigen::Vector2d, 3>& t,
                                 const Eigen::Vector2d& x) {
  const double o0 = orient2d_double(t[0], t[1], x);
  const double o1 = orient2d_double(t[1], t[2], x);
  const double o2 = orient2d_double(t[2], t[0], x);
  return (o0 >= 0.0 && o1 >= 0.0 && o2 >= 0.0) || (o0 <= 0.0 && o1 <= 0.0 && o2 <= 0.0);
}

/// a and b coplanar with normal n (any length).
inline bool coplanar_triangles_meet_double(const std::array<Eigen::Vector3d, 3>& a,
                                           const std::array<Eigen::Vector3d, 3>& b,
                                           const Eigen::Vector3d& n) {
  const Eigen::Vector3d m = n.cwiseAbs();
  const int k = m.x() > m.y() ? (m.x() > m.z() ? 0 : 2) : (m.y() > m.z() ? 1 : 2);
  const int i = (k + 1) % 3;
  const int j = (k + 2) % 3;
  std::array<Eigen::Vector2d, 3> a2;
  std::array<Eigen::Vector2d, 3> b2;
  for (int v = 0; v < 3; ++v) {
    a2[v] = Eigen::Vector2d(a[v][i], a[v][j]);
    b2[v] = Eigen::Vector2d(b[v][i], b[v][j]);
  }
  for (int e = 0; e < 3; ++e) {
    for (int f = 0; f < 3; ++f) {
      if (segments_meet_2d(a2[e], a2[(e + 1) % 3], b2[f], b2[(f + 1) % 3])) {
        return true;
      }
    }
  }
  return point_in_triangle_2d(b2, a2[0]) || point_in_triangle_2d(a2, b2[0]);
}

}  // namespace softbench::collision::detail
