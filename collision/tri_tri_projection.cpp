// SPDX-License-Identifier: MIT
#include "collision/tri_tri_projection.h"

#include "collision/exact_predicates.h"
#include "collision/tri_tri_projection_bounds.h"

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

// ------------------------------------------------------------------------------------------
// The computation frame, unnormalised. The thesis's frame (4-3) has unit axes n1 = e1 / |e1|,
// n3 = N / |N|, n2 = n3 x n1; here the axes are x* = e1, z* = N = e1 x e2 and y* = N x e1 (the
// same directions, lengths |e1|, |N|, |N| |e1|). Every decision below is a sign or a comparison
// of ratios, which a positive scaling of an axis does not change, so this is the same test
// without square roots or divisions, and its floating-point error bounds are a priori
// polynomials in the largest coordinate difference (collision/tri_tri_projection_bounds.h).

using namespace detail;  // the bounds of collision/tri_tri_projection_bounds.h
static_assert(kU == kUnitRoundoff && kFloor == kUnderflowFloor);

double max_abs(const Vec3& v) {
  return v.cwiseAbs().maxCoeff();
}

/// Triangle A's frame and its own extents on the x* and y* axes: P1 = (0, 0), P2 = (|e1|^2, 0),
/// P0 = (e1 . e2, y* . e2 = |N|^2).
struct Frame {
  Vec3 origin;  // P1
  Vec3 x_axis;  // e1 = P2 - P1
  Vec3 y_axis;  // N x e1
  Vec3 normal;  // N = e1 x e2, e2 = P0 - P1
  double x_low = 0.0, x_high = 0.0, y_high = 0.0;

  Frame(const Vec3& p0, const Vec3& p1, const Vec3& p2, const Vec3& normal_in)
      : origin(p1), x_axis(p2 - p1), y_axis(normal_in.cross(p2 - p1)), normal(normal_in) {
    const Vec3 e2 = p0 - p1;
    const double x0 = x_axis.dot(e2);
    x_low = std::min(0.0, x0);
    x_high = std::max(x_axis.dot(x_axis), x0);
    y_high = normal.squaredNorm();  // = y* . e2 = (N x e1) . e2
  }
};

/// Powers of M for the margins, with the underflow floor (below it nothing is rejected).
struct Margins {
  double crossing_x, crossing_y, vertex_x, vertex_y;
  explicit Margins(double m) {
    const double m2 = m * m;
    const double m4 = m2 * m2;
    crossing_x = kCrossingMarginX * m4 * m + kUnderflowFloor;
    crossing_y = kCrossingMarginY * m4 * m2 * m + kUnderflowFloor;
    vertex_x = kVertexMarginX * m2 + kUnderflowFloor;
    vertex_y = kVertexMarginY * m4 + kUnderflowFloor;
  }
};

/// An end of L_B in the frame, homogeneous: (nx / s, ny / s) with s >= 0, and the error bounds
/// of nx - c s and ny - c s for A's extents c.
struct FrameEnd {
  double nx = 0.0, ny = 0.0, s = 1.0, margin_x = 0.0, margin_y = 0.0;
};

/// The point of edge (a, b) of B on H, by the thesis's ratio t = |z_a| / (|z_a| + |z_b|) taken
/// from a: (|z_b| x_a + |z_a| x_b) / (|z_a| + |z_b|), kept as numerator and denominator.
FrameEnd crossing_end(const std::array<double, 3>& xs,
                      const std::array<double, 3>& ys,
                      const std::array<double, 3>& zs,
                      int a,
                      int b,
                      const Margins& margins) {
  const double za = std::abs(zs[a]);
  const double zb = std::abs(zs[b]);
  return {zb * xs[a] + za * xs[b], zb * ys[a] + za * ys[b], za + zb, margins.crossing_x,
          margins.crossing_y};
}

/// One axis of the frame: L_B's ends (n0 / s0, n1 / s1, numerators with error bounds m0, m1)
/// both below A's extent [low, high] on it or both above, by more than the rounding.
bool apart_on_axis(
    double n0, double s0, double m0, double n1, double s1, double m1, double low, double high) {
  return ((n0 - low * s0 < -m0) & (n1 - low * s1 < -m1))
         | ((n0 - high * s0 > m0) & (n1 - high * s1 > m1));
}

/// Early rejection on V (L_B's y* extent against A_v = [0, y_high]), then on W (x* against
/// A_w); only with a margin above the rounding, so touching triangles are never rejected.
bool rejected_on_v_or_w(const Frame& f, const FrameEnd& l, const FrameEnd& r) {
  return apart_on_axis(l.ny, l.s, l.margin_y, r.ny, r.s, r.margin_y, 0.0, f.y_high)
         || apart_on_axis(l.nx, l.s, l.margin_x, r.nx, r.s, r.margin_x, f.x_low, f.x_high);
}

/// Index of the vertex alone on its side when the signs s (all non-zero) are mixed.
int alone(const std::array<int, 3>& s) {
  return s[1] == s[2] ? 0 : (s[0] == s[2] ? 1 : 2);
}

/// Exact signs in floating point: three plane values against one certified bound, as bit
/// masks (bit i: value i > bound, resp. < -bound; neither: undecided in floating point).
struct SideMasks {
  unsigned positive = 0;
  unsigned negative = 0;

  bool one_side() const { return positive == 7u || negative == 7u; }
  bool all_decided() const { return (positive | negative) == 7u; }
  /// With all decided and mixed: the vertex alone on its side, and whether that side is +.
  int alone() const {
    constexpr int kAlone[8] = {0, 0, 1, 2, 2, 1, 0, 0};  // by `positive`: 1 -> 0, 3 -> 2, ...
    return kAlone[positive];
  }
  bool alone_positive() const { return positive == 1u || positive == 2u || positive == 4u; }
};

SideMasks side_masks(const std::array<double, 3>& v, double bound) {
  return {static_cast<unsigned>(v[0] > bound) | static_cast<unsigned>(v[1] > bound) << 1u
              | static_cast<unsigned>(v[2] > bound) << 2u,
          static_cast<unsigned>(v[0] < -bound) | static_cast<unsigned>(v[1] < -bound) << 1u
              | static_cast<unsigned>(v[2] < -bound) << 2u};
}

bool one_side(const std::array<int, 3>& s) {
  return (s[0] > 0 && s[1] > 0 && s[2] > 0) || (s[0] < 0 && s[1] < 0 && s[2] < 0);
}

/// All cases of figure 4.14 with exact signs of every decision (any input, including touching,
/// coplanar and degenerate triangles).
TriTriResult projection_exact(const Triangle& a, const Triangle& b_input) {
  // orient3d(P1, P2, P0, x) = ((P2 - P1) x (P0 - P1)) . (x - P1): the z* axis direction.
  const Plane plane_a(a[1], a[2], a[0]);
  std::array<double, 3> d;
  std::array<int, 3> s;
  for (int i = 0; i < 3; ++i) {
    s[i] = plane_a.side(b_input[i], d[i]);
  }
  if (one_side(s)) {
    return {};  // case (b)
  }
  const Plane plane_b(b_input[0], b_input[1], b_input[2]);
  const bool a_degenerate = plane_a.degenerate();
  const bool b_degenerate = plane_b.degenerate();
  if (a_degenerate || b_degenerate) {
    return degenerate_tri_tri(a, plane_a, a_degenerate, b_input, plane_b, b_degenerate);
  }
  const Frame frame(a[0], a[1], a[2], plane_a.normal);

  // Relabelling (a rotation, which keeps B's orientation): Q0 is the special vertex.
  const int zeros = (s[0] == 0 ? 1 : 0) + (s[1] == 0 ? 1 : 0) + (s[2] == 0 ? 1 : 0);
  int first = 0;
  if (zeros == 1) {
    first = s[0] == 0 ? 0 : (s[1] == 0 ? 1 : 2);  // cases (c), (e): Q0 on H
  } else if (zeros == 2) {
    first = s[0] != 0 ? 1 : (s[1] != 0 ? 2 : 0);  // case (d): Q0, Q1 on H, Q2 off
  } else if (zeros == 0) {
    first = alone(s);  // case (f): Q0 alone on its side
  }
  Triangle q;
  std::array<double, 3> z;   // z* coordinates (rounded); their exact signs are `sign`
  std::array<double, 3> xs;  // x* coordinates
  std::array<double, 3> ys;  // y* coordinates
  std::array<int, 3> sign;
  double m = std::max(max_abs(frame.x_axis), max_abs(a[0] - a[1]));
  for (int i = 0; i < 3; ++i) {
    const int k = (first + i) % 3;
    q[i] = b_input[k];
    sign[i] = s[k];
    const Vec3 w = q[i] - frame.origin;
    z[i] = d[k];
    xs[i] = frame.x_axis.dot(w);
    ys[i] = frame.y_axis.dot(w);
    m = std::max(m, max_abs(w));
  }
  const Margins margins(m);
  auto vertex_end = [&](int i) {
    return FrameEnd{xs[i], ys[i], 1.0, margins.vertex_x, margins.vertex_y};
  };

  // Case (a): B in H. V and W overlap of the projections, then coplanar triangles in H.
  if (zeros == 3) {
    auto lowest = [](const std::array<double, 3>& v) { return std::min({v[0], v[1], v[2]}); };
    auto highest = [](const std::array<double, 3>& v) { return std::max({v[0], v[1], v[2]}); };
    const FrameEnd low{lowest(xs), lowest(ys), 1.0, margins.vertex_x, margins.vertex_y};
    const FrameEnd high{highest(xs), highest(ys), 1.0, margins.vertex_x, margins.vertex_y};
    const bool v_apart = high.ny < -high.margin_y || low.ny - frame.y_high > low.margin_y;
    const bool w_apart =
        high.nx - frame.x_low < -high.margin_x || low.nx - frame.x_high > low.margin_x;
    if (v_apart || w_apart) {
      return {};
    }
    const auto [in_plane, orientation_a] = dominant_projection(plane_a);
    const int orientation_b = in_plane.orient(q[0], q[1], q[2]);
    return coplanar_triangles_intersect(in_plane, orientation_b, a, q) ? coplanar_result()
                                                                       : TriTriResult{};
  }

  // Case (c): B touches H at Q0 only; Q_L = Q_R = Q0.
  if (zeros == 1 && sign[1] == sign[2]) {
    if (rejected_on_v_or_w(frame, vertex_end(0), vertex_end(0))) {
      return {};
    }
    const auto [in_plane, orientation_a] = dominant_projection(plane_a);
    if (point_in_triangle(in_plane, orientation_a, a, q[0])) {
      return segment_result(q[0], q[0]);
    }
    return {};
  }

  // Cases (d), (e), (f): L_B's ends as points of B's edges, oriented from H's negative side to
  // its positive side (for the exact ordering).
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
  std::array<FrameEnd, 2> ends;
  for (int j = 0; j < 2; ++j) {
    const int from = lb[j].a;
    const int to = lb[j].b;
    if (sign[from] == 0 || sign[to] == 0) {
      ends[j] = vertex_end(sign[to] == 0 ? to : from);
    } else {
      ends[j] = crossing_end(xs, ys, z, from, to, margins);
    }
  }
  if (rejected_on_v_or_w(frame, ends[0], ends[1])) {
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
    const EdgePoint& c = lb[j];
    points[static_cast<std::size_t>(2 + j)] =
        crossing_point(q[c.a], q[c.b], sign[c.a], sign[c.b], z[c.a], z[c.b]);
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

/// Step 1 done and certified, not case (b): everything after it. A function of its own, kept out
/// of line, so that the common early out of case (b) does not set up this part's stack frame.
[[gnu::noinline]] TriTriResult projection_after_step_1(const Vec3& p0,
                                                       const Vec3& p1,
                                                       const Vec3& p2,
                                                       const Vec3& q0,
                                                       const Vec3& q1,
                                                       const Vec3& q2,
                                                       const Vec3& e1,
                                                       const Vec3& e2,
                                                       const Vec3& normal,
                                                       const std::array<double, 3>& z,
                                                       double m_a,
                                                       double m_w,
                                                       SideMasks sz) {
  const std::array<Vec3, 3> w = {q0 - p1, q1 - p1, q2 - p1};
  // Case (f) with certified signs (A and B are then proper triangles): Q0 alone on its side.
  const int first = sz.alone();
  const std::array<int, 3> k = {first, (first + 1) % 3, (first + 2) % 3};
  // L_B's ends on Q0Q1 and Q0Q2 by the ratio of the z* values, kept as numerator / denominator.
  const double z0 = std::abs(z[k[0]]);
  const double z1 = std::abs(z[k[1]]);
  const double z2 = std::abs(z[k[2]]);
  const double s01 = z0 + z1;
  const double s02 = z0 + z2;
  const double m = std::max(m_a, m_w);
  const double m2 = m * m;
  const double m5 = m2 * m2 * m;
  // V: y* = N x e1, A_v = [0, |N|^2].
  const Vec3 y_axis = normal.cross(e1);
  const std::array<double, 3> y = {y_axis.dot(w[0]), y_axis.dot(w[1]), y_axis.dot(w[2])};
  const double margin_y = kCrossingMarginY * m5 * m2 + kUnderflowFloor;
  const bool apart_v =
      apart_on_axis(z1 * y[k[0]] + z0 * y[k[1]], s01, margin_y, z2 * y[k[0]] + z0 * y[k[2]], s02,
                    margin_y, 0.0, normal.squaredNorm());
  // W: x* = e1, A_w = [min(0, x0), max(|e1|^2, x0)] with x0 = e1 . e2. Both rejections are
  // evaluated before one branch (random pairs make these branches unpredictable).
  const double x0 = e1.dot(e2);
  const double length = e1.squaredNorm();
  const std::array<double, 3> x = {e1.dot(w[0]), e1.dot(w[1]), e1.dot(w[2])};
  const double margin_x = kCrossingMarginX * m5 + kUnderflowFloor;
  const bool apart_w =
      apart_on_axis(z1 * x[k[0]] + z0 * x[k[1]], s01, margin_x, z2 * x[k[0]] + z0 * x[k[2]], s02,
                    margin_x, std::min(0.0, x0), std::max(length, x0));
  if (apart_v | apart_w) {
    return {};
  }

  // Clipping of L_B's line against A in H: e_i = orient3d(Q0, Q1, Q2, P_i), certified.
  const Vec3 f1 = q1 - q0;
  const Vec3 f2 = q2 - q0;
  const Vec3 normal_b = f1.cross(f2);
  const std::array<double, 3> e = {normal_b.dot(p0 - q0), normal_b.dot(p1 - q0),
                                   normal_b.dot(p2 - q0)};
  // The bound from step 1's magnitudes: |Q_i - Q0| <= 2 m_w and |P_i - Q0| <= m_a + m_w
  // (max norms, up to rounding that the bound's slack covers).
  const double m_b = 2.0 * m_w;
  const SideMasks se = side_masks(e, kSideBound * m_b * m_b * (m_a + m_w) + kUnderflowFloor);
  if (se.one_side()) {
    return {};  // the line misses A: no chord (figure 4.16, n = 0)
  }
  if (!se.all_decided()) {
    return projection_exact({p0, p1, p2}, {q0, q1, q2});
  }

  // Figure 4.15 on the line H x B-plane, direction D = N_A x N_B, parameter
  // lambda(x) = D . (x - P1). The chord runs between A's edges from the vertex P_a alone on its
  // side of B's plane; L_B between B's edges from Q0. With both triangles counter-clockwise
  // about their normals, the chord end on P_a P_(a+1) is the upper one (along D) when P_a is on
  // B's positive side, and L_B's end on Q0 Q1 the lower one when Q0 is on H's positive side.
  const int pa = se.alone();
  const bool a_positive = se.alone_positive();
  const bool q_positive = sz.alone_positive();
  const int a_low = a_positive ? (pa + 2) % 3 : (pa + 1) % 3;
  const int a_high = a_positive ? (pa + 1) % 3 : (pa + 2) % 3;
  const int b_low = q_positive ? 1 : 2;  // in the relabelled order k
  const int b_high = q_positive ? 2 : 1;
  const Vec3 direction = normal.cross(normal_b);
  const std::array<double, 3> lambda_a = {direction.dot(e2), 0.0, direction.dot(e1)};
  const std::array<double, 3> lambda_b = {direction.dot(w[k[0]]), direction.dot(w[k[1]]),
                                          direction.dot(w[k[2]])};
  // Ends as lambda numerators over positive denominators, by the same ratios as above.
  const std::array<double, 3> abs_e = {std::abs(e[0]), std::abs(e[1]), std::abs(e[2])};
  auto chord_end = [&](int other) {
    return std::pair(abs_e[other] * lambda_a[pa] + abs_e[pa] * lambda_a[other],
                     abs_e[pa] + abs_e[other]);
  };
  const std::array<double, 3> abs_z = {z0, z1, z2};
  auto lb_end = [&](int other) {
    return std::pair(abs_z[other] * lambda_b[0] + z0 * lambda_b[other], z0 + abs_z[other]);
  };
  const auto [c_low, sc_low] = chord_end(a_low);
  const auto [c_high, sc_high] = chord_end(a_high);
  const auto [l_low, sl_low] = lb_end(b_low);
  const auto [l_high, sl_high] = lb_end(b_high);
  // Signs of lambda(L_B high) - lambda(chord low) and lambda(L_B low) - lambda(chord high),
  // cross-multiplied (bound kOrderMargin). Within the margin, orient3d(Pa, Pb, Qc, Qd) with each
  // edge oriented from the negative to the positive side of the other's plane gives the same
  // sign exactly.
  const double m11 = m5 * m5 * m;
  const double order_margin = kOrderMargin * m11 + kUnderflowFloor;
  const double before_value = l_high * sc_low - c_low * sl_high;
  const double after_value = l_low * sc_high - c_high * sl_low;
  const Vec3* const pv[3] = {&p0, &p1, &p2};
  const Vec3* const qv[3] = {&q0, &q1, &q2};
  const Vec3& apex_a = *pv[pa];
  const Vec3& apex_b = *qv[k[0]];
  auto order = [&](double value, int a_other, int b_other) {
    if (std::abs(value) > order_margin) {
      return value > 0.0 ? 1 : -1;
    }
    const Vec3& a_far = *pv[a_other];
    const Vec3& b_far = *qv[k[b_other]];
    return orient3d(a_positive ? a_far : apex_a, a_positive ? apex_a : a_far,
                    q_positive ? b_far : apex_b, q_positive ? apex_b : b_far);
  };
  const int before = order(before_value, a_low, b_high);
  const int after = order(after_value, a_high, b_low);
  if ((before < 0) | (after > 0)) {
    return {};
  }

  // The segment: the later of the two lower ends to the earlier of the two upper ends (chosen
  // in floating point: where they are close either is right to rounding), interpolated along
  // its edge.
  auto a_point = [&](int other) {
    return apex_a + (e[pa] / (e[pa] - e[other])) * (*pv[other] - apex_a);
  };
  auto b_point = [&](int other) {
    return apex_b + (z[k[0]] / (z[k[0]] - z[k[other]])) * (*qv[k[other]] - apex_b);
  };
  const bool chord_starts = c_low * sl_low >= l_low * sc_low;
  const bool chord_ends = c_high * sl_high <= l_high * sc_high;
  return segment_result(chord_starts ? a_point(a_low) : b_point(b_low),
                        chord_ends ? a_point(a_high) : b_point(b_high));
}

}  // namespace

TriTriResult tri_tri_projection(const Vec3& p0,
                                const Vec3& p1,
                                const Vec3& p2,
                                const Vec3& q0,
                                const Vec3& q1,
                                const Vec3& q2) {
  // Step 1: B's vertices against H, z* = N . (Q_i - P1) with N = (P2 - P1) x (P0 - P1), signs
  // certified by a bound computed once for the three (semi-static filter).
  const Vec3 e1 = p2 - p1;
  const Vec3 e2 = p0 - p1;
  const Vec3 normal = e1.cross(e2);
  const Vec3 w0 = q0 - p1, w1 = q1 - p1, w2 = q2 - p1;
  const std::array<double, 3> z = {normal.dot(w0), normal.dot(w1), normal.dot(w2)};
  const double m_a = std::max(max_abs(e1), max_abs(e2));
  const double m_w = std::max({max_abs(w0), max_abs(w1), max_abs(w2)});
  if (!(std::max(m_a, m_w) < kMaxMagnitude)) {
    return projection_exact({p0, p1, p2}, {q0, q1, q2});  // the bounds could overflow
  }
  const SideMasks sz = side_masks(z, kSideBound * m_a * m_a * m_w + kUnderflowFloor);
  // Case (b): B strictly on one side of H (the common early out).
  if (sz.one_side()) {
    return {};
  }
  if (!sz.all_decided()) {
    // A vertex of B on H or within rounding of it: exact signs, all cases of figure 4.14.
    return projection_exact({p0, p1, p2}, {q0, q1, q2});
  }
  return projection_after_step_1(p0, p1, p2, q0, q1, q2, e1, e2, normal, z, m_a, m_w, sz);
}

}  // namespace softbench::collision
