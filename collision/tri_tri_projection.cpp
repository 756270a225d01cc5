// SPDX-License-Identifier: MIT
#include "collision/tri_tri_projection.h"

#include "collision/exact_predicates.h"

#include <Eigen/Geometry>

#include <algorithm>
#include <array>
#include <cmath>
#include <limits>
#include <utility>

namespace softbench::collision {
namespace {

using Vec3 = Eigen::Vector3d;
using Triangle = std::array<Vec3, 3>;

/// Rounding error of a frame coordinate relative to (conditioning + 1) * extent: the frame's
/// axes and a dot product cost a few dozen ulps at most; 64 leaves a wide margin.
constexpr double kFrameError = 64.0 * kUnitRoundoff;
constexpr double kInfinity = std::numeric_limits<double>::infinity();

/// A triangle's plane with what the filtered orient3d needs, computed once per triangle:
/// value(x) = normal . (x - a) = det[b - a, c - a, x - a], and the permanent weights.
struct Plane {
  Vec3 a, b, c;
  Vec3 normal;      // (b - a) x (c - a), unnormalised
  Vec3 abs_minors;  // |u_y v_z| + |u_z v_y|, ...: the permanent is abs_minors . |x - a|

  Plane(const Vec3& a_in, const Vec3& b_in, const Vec3& c_in) : a(a_in), b(b_in), c(c_in) {
    const Vec3 u = b - a;
    const Vec3 v = c - a;
    normal = Vec3(u.y() * v.z() - u.z() * v.y(), u.z() * v.x() - u.x() * v.z(),
                  u.x() * v.y() - u.y() * v.x());
    abs_minors = Vec3(std::abs(u.y() * v.z()) + std::abs(u.z() * v.y()),
                      std::abs(u.z() * v.x()) + std::abs(u.x() * v.z()),
                      std::abs(u.x() * v.y()) + std::abs(u.y() * v.x()));
  }

  /// Exact side of x (+1 on the normal's side) and the floating-point value of the determinant.
  int side(const Vec3& x, double& value) const {
    const Vec3 w = x - a;
    value = normal.dot(w);
    return filtered_sign(value, kOrient3dErrorBound * abs_minors.dot(w.cwiseAbs()), [&] {
      detail::count_orient3d_fallback();
      return orient3d_exact(a, b, c, x);
    });
  }

  /// Exact sign of the normal's component k (= orient2d of the triangle with coordinate k
  /// dropped, in the cyclic order (k+1, k+2)).
  int normal_sign(int k) const {
    const int i = (k + 1) % 3;
    const int j = (k + 2) % 3;
    return filtered_sign(normal[k], kOrient2dErrorBound * abs_minors[k], [&] {
      detail::count_orient2d_fallback();
      return orient2d_exact(a[i], a[j], b[i], b[j], c[i], c[j]);
    });
  }

  /// Exactly zero area (collinear vertices). Cheap when the float normal is clearly non-zero.
  bool degenerate() const {
    for (int k = 0; k < 3; ++k) {
      if (std::abs(normal[k]) > kOrient2dErrorBound * abs_minors[k] + kUnderflowFloor) {
        return false;
      }
    }
    return normal_sign(0) == 0 && normal_sign(1) == 0 && normal_sign(2) == 0;
  }
};

/// Exact orientation in the coordinate plane that drops axis k (cyclic order keeps the sign of
/// normal[k] as the orientation of a counter-clockwise triangle).
struct InPlane {
  int i = 0;
  int j = 1;
  int orient(const Vec3& p, const Vec3& q, const Vec3& r) const {
    return orient2d(p[i], p[j], q[i], q[j], r[i], r[j]);
  }
};

/// The projection for in-plane tests of points lying exactly in `plane`: drop the coordinate
/// where the normal is largest (any k with an exactly non-zero component is valid). Returns the
/// projection and the orientation sign of the plane's triangle in it.
std::pair<InPlane, int> dominant_projection(const Plane& plane) {
  std::array<int, 3> axes = {0, 1, 2};
  std::sort(axes.begin(), axes.end(),
            [&](int l, int r) { return std::abs(plane.normal[l]) > std::abs(plane.normal[r]); });
  for (const int k : axes) {
    const int sign = plane.normal_sign(k);
    if (sign != 0) {
      return {InPlane{(k + 1) % 3, (k + 2) % 3}, sign};
    }
  }
  return {InPlane{}, 0};  // degenerate plane: callers exclude it
}

/// Figure 4.18: point x (exactly in the plane of t) in the closed triangle t, by same-side tests
/// against its three edges. `orientation` is t's orientation in the projection.
bool point_in_triangle(const InPlane& plane, int orientation, const Triangle& t, const Vec3& x) {
  for (int i = 0; i < 3; ++i) {
    if (plane.orient(t[i], t[(i + 1) % 3], x) * orientation < 0) {
      return false;
    }
  }
  return true;
}

/// A point of a segment's line on the edge (a, b) of a triangle, oriented so that the
/// characteristic value rises strictly from a to b (a vertex on the line is (k, j) or (j, k)
/// with j the neighbour off the line). This orientation makes the collinear-overlap predicate's
/// sign consistent (see overlap_on_line).
struct EdgePoint {
  int a = 0;
  int b = 0;
};

/// Figure 4.16's clipping pseudo-code: the points where the line (characteristic values with
/// signs `e`, not all zero) meets the closed triangle. Returns how many (0, 1 or 2); a vertex
/// on the line counts as a point, as in the thesis (which may list P0 twice).
int clip_triangle(const std::array<int, 3>& e, std::array<EdgePoint, 2>& points) {
  auto vertex_point = [&](int k) {
    const int j = e[(k + 1) % 3] != 0 ? (k + 1) % 3 : (k + 2) % 3;
    return e[j] > 0 ? EdgePoint{k, j} : EdgePoint{j, k};
  };
  int n = 0;
  if (e[0] == 0) {
    points[n++] = vertex_point(0);
  }
  for (int i = 0; i < 3 && n < 2; ++i) {
    const int next = (i + 1) % 3;
    if (e[next] == 0) {
      points[n++] = vertex_point(next);
    } else if (e[i] * e[next] < 0) {
      points[n++] = e[i] < 0 ? EdgePoint{i, next} : EdgePoint{next, i};
    }
  }
  return n;
}

/// Figure 4.15 with exact comparisons: two collinear segments (each 1 or 2 points) are
/// disjoint exactly when every point of one lies strictly on the same side of every point of the
/// other. `order(x, y)` is the sign of y's position relative to x along the line, up to one
/// global sign shared by all calls.
template <typename Order>
bool overlap_on_line(int nx, int ny, Order&& order) {
  bool all_positive = true;
  bool all_negative = true;
  for (int i = 0; i < nx; ++i) {
    for (int j = 0; j < ny; ++j) {
      const int s = order(i, j);
      all_positive = all_positive && s > 0;
      all_negative = all_negative && s < 0;
      if (!all_positive && !all_negative) {
        return true;
      }
    }
  }
  return false;
}

/// In-plane segment (y0, y1) against the closed triangle t, all exactly coplanar (cases (a) and
/// degenerate B): clipping with e_i = orient2d(y0, y1, P_i), then the collinear overlap. For a
/// point on t's edge (a, b) and an end y of the segment, orient2d(Pa, Pb, y) orders them.
bool segment_meets_triangle_in_plane(const InPlane& plane,
                                     const Triangle& t,
                                     const Vec3& y0,
                                     const Vec3& y1) {
  const std::array<int, 3> e = {plane.orient(y0, y1, t[0]), plane.orient(y0, y1, t[1]),
                                plane.orient(y0, y1, t[2])};
  std::array<EdgePoint, 2> chord;
  const int n = clip_triangle(e, chord);
  if (n == 0) {
    return false;
  }
  const std::array<const Vec3*, 2> ends = {&y0, &y1};
  return overlap_on_line(
      n, 2, [&](int i, int j) { return plane.orient(t[chord[i].a], t[chord[i].b], *ends[j]); });
}

/// Figure 4.17: coplanar triangles intersect when an edge of B meets A or A lies inside B.
bool coplanar_triangles_intersect(const InPlane& plane,
                                  int b_orientation,
                                  const Triangle& a,
                                  const Triangle& b) {
  for (int i = 0; i < 3; ++i) {
    if (segment_meets_triangle_in_plane(plane, a, b[i], b[(i + 1) % 3])) {
      return true;
    }
  }
  return point_in_triangle(plane, b_orientation, b, a[0]);
}

TriTriResult segment_result(const Vec3& a, const Vec3& b) {
  TriTriResult result;
  result.contact = TriTriContact::kSegment;
  result.a = a;
  result.b = b;
  return result;
}

TriTriResult coplanar_result() {
  TriTriResult result;
  result.contact = TriTriContact::kCoplanar;
  return result;
}

/// Point of edge (from, to) where a linear function with values v_from, v_to (signs s_from,
/// s_to, exact) vanishes: the ratio t = |v| / (|v| + |v'|) of (4-10), exact at the vertices.
Vec3 crossing_point(
    const Vec3& from, const Vec3& to, int s_from, int s_to, double v_from, double v_to) {
  if (s_from == 0) {
    return from;
  }
  if (s_to == 0) {
    return to;
  }
  const double sum = std::abs(v_from) + std::abs(v_to);
  const double t = sum > 0.0 ? std::abs(v_from) / sum : 0.5;
  return from + t * (to - from);
}

// ------------------------------------------------------------------------------------------
// Degenerate (zero-area) triangles: reduced exactly to the segment or point they span.

struct Hull {
  int count = 1;  // 1: point p[0]; 2: segment p[0] p[1]
  std::array<Vec3, 2> p;
};

/// Collinear vertices: the extreme pair along the axis of largest spread (ordering along a
/// coordinate is exact for collinear points when the line is not perpendicular to it).
Hull reduce_degenerate(const Triangle& t) {
  int axis = 0;
  double best = -1.0;
  for (int k = 0; k < 3; ++k) {
    const double lo = std::min({t[0][k], t[1][k], t[2][k]});
    const double hi = std::max({t[0][k], t[1][k], t[2][k]});
    if (hi - lo > best) {
      best = hi - lo;
      axis = k;
    }
  }
  Hull hull;
  if (best == 0.0) {
    hull.p[0] = t[0];
    return hull;
  }
  int lo = 0;
  int hi = 0;
  for (int i = 1; i < 3; ++i) {
    lo = t[i][axis] < t[lo][axis] ? i : lo;
    hi = t[i][axis] > t[hi][axis] ? i : hi;
  }
  hull.count = 2;
  hull.p = {t[lo], t[hi]};
  return hull;
}

/// x exactly on the line of (s0, s1) (all three coordinate projections collinear).
bool collinear(const Vec3& s0, const Vec3& s1, const Vec3& x) {
  for (int k = 0; k < 3; ++k) {
    const InPlane plane{(k + 1) % 3, (k + 2) % 3};
    if (plane.orient(s0, s1, x) != 0) {
      return false;
    }
  }
  return true;
}

/// x collinear with (s0, s1) lies between them: a coordinate-wise box test, exact then.
bool between(const Vec3& s0, const Vec3& s1, const Vec3& x) {
  for (int k = 0; k < 3; ++k) {
    if (x[k] < std::min(s0[k], s1[k]) || x[k] > std::max(s0[k], s1[k])) {
      return false;
    }
  }
  return true;
}

TriTriResult hull_vs_hull(const Hull& s, const Hull& t) {
  if (s.count == 1 && t.count == 1) {
    return s.p[0] == t.p[0] ? segment_result(s.p[0], s.p[0]) : TriTriResult{};
  }
  if (s.count == 1 || t.count == 1) {
    const Hull& segment = s.count == 2 ? s : t;
    const Vec3& x = s.count == 1 ? s.p[0] : t.p[0];
    const bool on =
        collinear(segment.p[0], segment.p[1], x) && between(segment.p[0], segment.p[1], x);
    return on ? segment_result(x, x) : TriTriResult{};
  }
  const Vec3 &s0 = s.p[0], &s1 = s.p[1], &t0 = t.p[0], &t1 = t.p[1];
  if (orient3d(s0, s1, t0, t1) != 0) {
    return {};
  }
  if (collinear(s0, s1, t0) && collinear(s0, s1, t1)) {
    // Collinear overlap: order the four points along the axis of largest spread of s.
    int axis = 0;
    for (int k = 1; k < 3; ++k) {
      axis = std::abs(s1[k] - s0[k]) > std::abs(s1[axis] - s0[axis]) ? k : axis;
    }
    auto lower = [&](const Vec3& p, const Vec3& q) { return p[axis] < q[axis] ? p : q; };
    auto upper = [&](const Vec3& p, const Vec3& q) { return p[axis] < q[axis] ? q : p; };
    const Vec3 start = upper(lower(s0, s1), lower(t0, t1));
    const Vec3 end = lower(upper(s0, s1), upper(t0, t1));
    if (start[axis] > end[axis]) {
      return {};
    }
    return segment_result(start, end);
  }
  // Coplanar, not collinear: a projection where t0 or t1 is off s's line is injective on the
  // common plane; there the classic 2D segment test is exact.
  for (int k = 0; k < 3; ++k) {
    const InPlane plane{(k + 1) % 3, (k + 2) % 3};
    const int o0 = plane.orient(s0, s1, t0);
    const int o1 = plane.orient(s0, s1, t1);
    if (o0 == 0 && o1 == 0) {
      continue;
    }
    const int o2 = plane.orient(t0, t1, s0);
    const int o3 = plane.orient(t0, t1, s1);
    if (o0 * o1 > 0 || o2 * o3 > 0) {
      return {};
    }
    // Crossing point, floating point: where s meets t's line.
    const double v2 = (t1 - t0).cross(s0 - t0).norm();
    const double v3 = (t1 - t0).cross(s1 - t0).norm();
    return segment_result(crossing_point(s0, s1, o2, o3, v2, v3),
                          crossing_point(s0, s1, o2, o3, v2, v3));
  }
  return {};  // unreachable: some t point is off s's line
}

/// Degenerate `hull` against the proper triangle `t` with plane `plane`.
TriTriResult hull_vs_triangle(const Hull& hull, const Triangle& t, const Plane& plane) {
  const auto [in_plane, orientation] = dominant_projection(plane);
  double v0 = 0.0;
  const int s0 = plane.side(hull.p[0], v0);
  if (hull.count == 1) {
    if (s0 == 0 && point_in_triangle(in_plane, orientation, t, hull.p[0])) {
      return segment_result(hull.p[0], hull.p[0]);
    }
    return {};
  }
  double v1 = 0.0;
  const int s1 = plane.side(hull.p[1], v1);
  if (s0 * s1 > 0) {
    return {};
  }
  if (s0 == 0 && s1 == 0) {
    return segment_meets_triangle_in_plane(in_plane, t, hull.p[0], hull.p[1]) ? coplanar_result()
                                                                              : TriTriResult{};
  }
  if (s0 == 0 || s1 == 0) {
    const Vec3& x = s0 == 0 ? hull.p[0] : hull.p[1];
    return point_in_triangle(in_plane, orientation, t, x) ? segment_result(x, x) : TriTriResult{};
  }
  // Proper crossing: the line meets the closed triangle when the three volumes against its
  // edges do not have opposite strict signs.
  const std::array<int, 3> o = {orient3d(hull.p[0], hull.p[1], t[0], t[1]),
                                orient3d(hull.p[0], hull.p[1], t[1], t[2]),
                                orient3d(hull.p[0], hull.p[1], t[2], t[0])};
  const bool positive = o[0] > 0 || o[1] > 0 || o[2] > 0;
  const bool negative = o[0] < 0 || o[1] < 0 || o[2] < 0;
  if (positive && negative) {
    return {};
  }
  const Vec3 x = crossing_point(hull.p[0], hull.p[1], s0, s1, v0, v1);
  return segment_result(x, x);
}

TriTriResult degenerate_tri_tri(const Triangle& a,
                                const Plane& plane_a,
                                bool a_degenerate,
                                const Triangle& b,
                                const Plane& plane_b,
                                bool b_degenerate) {
  if (a_degenerate && b_degenerate) {
    return hull_vs_hull(reduce_degenerate(a), reduce_degenerate(b));
  }
  if (b_degenerate) {
    return hull_vs_triangle(reduce_degenerate(b), a, plane_a);
  }
  return hull_vs_triangle(reduce_degenerate(a), b, plane_b);
}

}  // namespace

TriTriResult tri_tri_projection(const Vec3& p0,
                                const Vec3& p1,
                                const Vec3& p2,
                                const Vec3& q0,
                                const Vec3& q1,
                                const Vec3& q2) {
  const Triangle a = {p0, p1, p2};
  // orient3d(P1, P2, P0, x) = ((P2 - P1) x (P0 - P1)) . (x - P1): the z* axis direction.
  const Plane plane_a(p1, p2, p0);

  // Step 1: B's vertices against H (the sign of z*), exact.
  std::array<double, 3> d;
  std::array<int, 3> s;
  const Triangle b_input = {q0, q1, q2};
  for (int i = 0; i < 3; ++i) {
    s[i] = plane_a.side(b_input[i], d[i]);
  }
  // Case (b): B strictly on one side of H (checked before anything else: the common early out).
  if ((s[0] > 0 && s[1] > 0 && s[2] > 0) || (s[0] < 0 && s[1] < 0 && s[2] < 0)) {
    return {};
  }
  const Plane plane_b(q0, q1, q2);
  const bool a_degenerate = plane_a.degenerate();
  const bool b_degenerate = plane_b.degenerate();
  if (a_degenerate || b_degenerate) {
    return degenerate_tri_tri(a, plane_a, a_degenerate, b_input, plane_b, b_degenerate);
  }

  // Step 2: the computation frame (4-3): n1 along P1P2, n3 along A's normal, n2 = n3 x n1.
  const Vec3 e1 = p2 - p1;
  const Vec3 e2 = p0 - p1;
  const double length = e1.norm();
  const double normal_norm = plane_a.normal.norm();
  const Vec3 n1 = e1 / length;
  const Vec3 n3 = plane_a.normal / normal_norm;
  const Vec3 n2 = n3.cross(n1);
  // A in the frame: P1 = (0, 0), P2 = (length, 0), P0 = (x0, h).
  const double x0 = n1.dot(e2);
  const double h = n2.dot(e2);

  // Relabelling (coordinate rotation, which keeps B's orientation): Q0 is the special vertex.
  int zeros = 0;
  for (const int si : s) {
    zeros += si == 0 ? 1 : 0;
  }
  int first = 0;
  if (zeros == 1) {
    first = s[0] == 0 ? 0 : (s[1] == 0 ? 1 : 2);  // cases (c), (e): Q0 on H
  } else if (zeros == 2) {
    first = s[0] != 0 ? 1 : (s[1] != 0 ? 2 : 0);  // case (d): Q0, Q1 on H, Q2 off
  } else if (zeros == 0) {
    first = s[1] == s[2] ? 0 : (s[0] == s[2] ? 1 : 2);  // case (f): Q0 alone on its side
  }
  std::array<Vec3, 3> q;
  std::array<double, 3> z;   // z* coordinates (rounded); their signs are s
  std::array<double, 3> xs;  // x* coordinates
  std::array<double, 3> ys;  // y* coordinates
  std::array<int, 3> sign;
  double extent = std::max(length, e2.norm());
  for (int i = 0; i < 3; ++i) {
    const int k = (first + i) % 3;
    q[i] = b_input[k];
    sign[i] = s[k];
    const Vec3 w = q[i] - p1;
    z[i] = d[k] / normal_norm;
    xs[i] = n1.dot(w);
    ys[i] = n2.dot(w);
    extent = std::max(extent, w.norm());
  }
  // Error of any frame coordinate: the normal's direction is as well conditioned as A's angle
  // at P1, |e1| |e2| / |N| = 1 / sin(angle).
  const double conditioning = length * e2.norm() / normal_norm;
  const double frame_error = kFrameError * (conditioning + 1.0) * extent;
  const double av_low = -frame_error;  // A_v = [0, h] on the y* axis, widened by the error
  const double av_high = h + frame_error;
  const double aw_low = std::min(0.0, x0) - frame_error;  // A_w on the x* axis
  const double aw_high = std::max(length, x0) + frame_error;

  // Case (a): B in H. V and W overlap of the projections, then coplanar triangles in H.
  if (zeros == 3) {
    const double y_low = std::min({ys[0], ys[1], ys[2]}) - frame_error;
    const double y_high = std::max({ys[0], ys[1], ys[2]}) + frame_error;
    if (y_high < av_low || y_low > av_high) {
      return {};
    }
    const double x_low = std::min({xs[0], xs[1], xs[2]}) - frame_error;
    const double x_high = std::max({xs[0], xs[1], xs[2]}) + frame_error;
    if (x_high < aw_low || x_low > aw_high) {
      return {};
    }
    const auto [in_plane, orientation_a] = dominant_projection(plane_a);
    const int orientation_b = in_plane.orient(q[0], q[1], q[2]);
    return coplanar_triangles_intersect(in_plane, orientation_b, a, q) ? coplanar_result()
                                                                       : TriTriResult{};
  }

  // Case (c): B touches H at Q0 only; Q_L = Q_R = Q0.
  if (zeros == 1 && sign[1] == sign[2]) {
    if (ys[0] < av_low || ys[0] > av_high || xs[0] < aw_low || xs[0] > aw_high) {
      return {};
    }
    const auto [in_plane, orientation_a] = dominant_projection(plane_a);
    if (point_in_triangle(in_plane, orientation_a, a, q[0])) {
      return segment_result(q[0], q[0]);
    }
    return {};
  }

  // Cases (d), (e), (f): L_B's ends as points of B's edges, oriented from H's negative side to
  // its positive side (for the exact ordering), with their frame coordinates and error margins.
  std::array<EdgePoint, 2> lb;
  if (zeros == 2) {  // (d): Q_L = Q0, Q_R = Q1, both reached along the edges from Q2
    lb[0] = sign[2] > 0 ? EdgePoint{0, 2} : EdgePoint{2, 0};
    lb[1] = sign[2] > 0 ? EdgePoint{1, 2} : EdgePoint{2, 1};
  } else if (zeros == 1) {  // (e): Q_L = Q0 (along Q0Q1), Q_R on Q1Q2
    lb[0] = sign[1] > 0 ? EdgePoint{0, 1} : EdgePoint{1, 0};
    lb[1] = sign[1] > 0 ? EdgePoint{2, 1} : EdgePoint{1, 2};
  } else {  // (f): Q_L on Q0Q1, Q_R on Q0Q2
    lb[0] = sign[0] > 0 ? EdgePoint{1, 0} : EdgePoint{0, 1};
    lb[1] = sign[0] > 0 ? EdgePoint{2, 0} : EdgePoint{0, 2};
  }
  std::array<double, 2> lx;
  std::array<double, 2> ly;
  std::array<double, 2> margin;
  std::array<double, 2> ratio;  // t of (4-10): the point is q[b] + t (q[a] - q[b])
  for (int j = 0; j < 2; ++j) {
    const int from = lb[j].a;
    const int to = lb[j].b;
    if (sign[from] == 0 || sign[to] == 0) {
      ratio[j] = sign[to] == 0 ? 0.0 : 1.0;
      const int vertex = sign[to] == 0 ? to : from;
      lx[j] = xs[vertex];
      ly[j] = ys[vertex];
      margin[j] = frame_error;
      continue;
    }
    const double sum = std::abs(z[from]) + std::abs(z[to]);
    if (!(sum > 0.0)) {
      ratio[j] = 0.5;
      lx[j] = 0.5 * (xs[from] + xs[to]);
      ly[j] = 0.5 * (ys[from] + ys[to]);
      margin[j] = kInfinity;
      continue;
    }
    const double t = std::abs(z[to]) / sum;
    ratio[j] = t;
    lx[j] = xs[to] + t * (xs[from] - xs[to]);
    ly[j] = ys[to] + t * (ys[from] - ys[to]);
    // t's error is at most 2 frame_error / sum; it moves the point along the edge.
    const double spread = std::max(std::abs(xs[from] - xs[to]), std::abs(ys[from] - ys[to]));
    margin[j] = 3.0 * frame_error + 2.0 * frame_error * spread / sum;
  }
  // Early rejection on V: L_B's projection on the y* axis against A_v.
  if ((ly[0] + margin[0] < av_low && ly[1] + margin[1] < av_low)
      || (ly[0] - margin[0] > av_high && ly[1] - margin[1] > av_high)) {
    return {};
  }
  // Then on W: the x* axis against A_w.
  if ((lx[0] + margin[0] < aw_low && lx[1] + margin[1] < aw_low)
      || (lx[0] - margin[0] > aw_high && lx[1] - margin[1] > aw_high)) {
    return {};
  }

  // L_B against A_H: clipping with e_i = orient3d(Q0, Q1, Q2, P_i) (exact signs; the
  // relabelling is a rotation, so B's plane keeps its orientation).
  std::array<double, 3> e_value;
  std::array<int, 3> e;
  for (int i = 0; i < 3; ++i) {
    e[i] = plane_b.side(a[i], e_value[i]);
  }
  std::array<EdgePoint, 2> chord;
  const int n = clip_triangle(e, chord);
  if (n == 0) {
    return {};
  }
  const bool overlap = overlap_on_line(n, 2, [&](int i, int j) {
    return orient3d(a[chord[i].a], a[chord[i].b], q[lb[j].a], q[lb[j].b]);
  });
  if (!overlap) {
    return {};
  }

  // The segment: the overlap of the chord and L_B along the line, in world coordinates.
  std::array<Vec3, 4> points;
  for (int i = 0; i < 2; ++i) {
    const EdgePoint& c = chord[std::min(i, n - 1)];
    points[static_cast<std::size_t>(i)] =
        crossing_point(a[c.a], a[c.b], e[c.a], e[c.b], e_value[c.a], e_value[c.b]);
  }
  for (int j = 0; j < 2; ++j) {
    const Vec3& qa = q[lb[j].a];
    const Vec3& qb = q[lb[j].b];
    points[static_cast<std::size_t>(2 + j)] = qb + ratio[j] * (qa - qb);
  }
  const Vec3 direction = plane_a.normal.cross(plane_b.normal);
  std::array<double, 4> param;
  for (std::size_t k = 0; k < 4; ++k) {
    param[k] = direction.dot(points[k]);
  }
  const std::size_t chord_low = param[0] <= param[1] ? 0 : 1;
  const std::size_t lb_low = param[2] <= param[3] ? 2 : 3;
  const std::size_t low = param[chord_low] >= param[lb_low] ? chord_low : lb_low;
  const std::size_t chord_high = 1 - chord_low;
  const std::size_t lb_high = 5 - lb_low;
  const std::size_t high = param[chord_high] <= param[lb_high] ? chord_high : lb_high;
  return segment_result(points[low], points[high]);
}

}  // namespace softbench::collision
