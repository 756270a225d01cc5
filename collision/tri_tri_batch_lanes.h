// SPDX-License-Identifier: MIT
#pragma once

// The lane kernel of collision/tri_tri_batch.cpp: the scalar projection test's certified fast
// path (case (b), V and W, the clipping signs and the order on the line; bounds from
// collision/tri_tri_projection_bounds.h) for a block of lanes without branches. Written once
// against an `Ops` type that supplies the vector type, its lane masks and the few operations
// whose spelling differs between GCC's generic vectors and AVX-512 intrinsics (comparisons,
// blends, abs, max). Internal: included by tri_tri_batch.cpp and tri_tri_batch_avx512.cpp only,
// whose instantiations stay local to each (anonymous namespace) so that code compiled for
// AVX-512 never leaks into the baseline build.

#include "collision/tri_tri_projection_bounds.h"

#include <cstddef>
#include <cstdint>

// The lane operations pass 32- and 64-byte vectors by value; they are always inlined into the
// kernels and local to their translation unit, so the ABI GCC warns about when such a function
// is compiled without AVX is never used.
#pragma GCC diagnostic ignored "-Wpsabi"

namespace softbench::collision::detail {

/// Raw, non-aliasing views of one structure-of-arrays triangle set.
struct Columns {
  const double* __restrict x0;
  const double* __restrict y0;
  const double* __restrict z0;
  const double* __restrict x1;
  const double* __restrict y1;
  const double* __restrict z1;
  const double* __restrict x2;
  const double* __restrict y2;
  const double* __restrict z2;
};

inline constexpr std::uint8_t kLaneDisjoint = 0;
inline constexpr std::uint8_t kLaneIntersect = 1;
inline constexpr std::uint8_t kLaneUndecided = 2;

/// The AVX-512 kernel (collision/tri_tri_batch_avx512.cpp): status of pairs [0, count), count a
/// multiple of 8. Call only when the CPU has AVX-512 F and DQ.
void classify_avx512(const Columns& a, const Columns& b, std::size_t count, std::uint8_t* status);

namespace {

#define SOFTBENCH_LANES_INLINE inline __attribute__((always_inline))

template <typename V>
struct V3 {
  V x, y, z;
};

template <typename V>
SOFTBENCH_LANES_INLINE V3<V> sub(const V3<V>& a, const V3<V>& b) {
  return {a.x - b.x, a.y - b.y, a.z - b.z};
}
template <typename V>
SOFTBENCH_LANES_INLINE V3<V> cross(const V3<V>& a, const V3<V>& b) {
  return {a.y * b.z - a.z * b.y, a.z * b.x - a.x * b.z, a.x * b.y - a.y * b.x};
}
template <typename V>
SOFTBENCH_LANES_INLINE V dot(const V3<V>& a, const V3<V>& b) {
  return a.x * b.x + a.y * b.y + a.z * b.z;
}

/// Certified signs of three plane values against one bound, per lane.
template <typename Ops>
struct Sides {
  using V = typename Ops::V;
  using Mask = typename Ops::Mask;
  Mask positive[3];  // value > bound
  Mask one_side;     // all three certainly on one side
  Mask decided;      // all three certain (|value| > bound)
  Sides(V v0, V v1, V v2, V bound)
      : positive{Ops::greater(v0, bound), Ops::greater(v1, bound), Ops::greater(v2, bound)} {
    const Mask n0 = Ops::less(v0, -bound);
    const Mask n1 = Ops::less(v1, -bound);
    const Mask n2 = Ops::less(v2, -bound);
    one_side = (positive[0] & positive[1] & positive[2]) | (n0 & n1 & n2);
    decided = (positive[0] | n0) & (positive[1] | n1) & (positive[2] | n2);
  }
};

/// Per lane, the vertex alone on its side (vertex 0, 1 or 2) from the positive masks of three
/// decided, mixed signs; `at(k, ...)` picks the value k places after that vertex.
template <typename Ops>
struct Rotation {
  using V = typename Ops::V;
  using Mask = typename Ops::Mask;
  Mask first, second;  // the alone vertex is 0, resp. 1 (else 2)
  Rotation(Mask p0, Mask p1, Mask p2) : first(~(p1 ^ p2)), second(~first & ~(p0 ^ p2)) {}
  SOFTBENCH_LANES_INLINE V at(int k, V v0, V v1, V v2) const {
    const V v[3] = {v0, v1, v2};
    return Ops::select(first, v[k % 3], Ops::select(second, v[(k + 1) % 3], v[(k + 2) % 3]));
  }
  SOFTBENCH_LANES_INLINE Mask alone(Mask p0, Mask p1, Mask p2) const {
    return (first & p0) | (~first & ((second & p1) | (~second & p2)));
  }
};

/// Where a triangle crosses the other's plane: the ends on the edges from its apex (the vertex
/// alone on its side) to the next and previous vertices, as numerators of a coordinate lambda
/// over positive weights, by the ratios of the plane values' magnitudes d.
template <typename V>
struct LineEnds {
  V low, low_weight, high, high_weight;
};

template <typename Ops, typename V = typename Ops::V>
SOFTBENCH_LANES_INLINE LineEnds<V> line_ends(const Rotation<Ops>& apex,
                                             typename Ops::Mask next_is_upper,
                                             V lambda0,
                                             V lambda1,
                                             V lambda2,
                                             V d0,
                                             V d1,
                                             V d2) {
  const V l_apex = apex.at(0, lambda0, lambda1, lambda2);
  const V d_apex = apex.at(0, d0, d1, d2);
  const V d_next = apex.at(1, d0, d1, d2);
  const V d_prev = apex.at(2, d0, d1, d2);
  const V next = d_next * l_apex + d_apex * apex.at(1, lambda0, lambda1, lambda2);
  const V prev = d_prev * l_apex + d_apex * apex.at(2, lambda0, lambda1, lambda2);
  return {Ops::select(next_is_upper, prev, next),
          Ops::select(next_is_upper, d_apex + d_prev, d_apex + d_next),
          Ops::select(next_is_upper, next, prev),
          Ops::select(next_is_upper, d_apex + d_next, d_apex + d_prev)};
}

/// Both ends (n / s, error bound m) below [low, high] or both above, beyond the margin.
template <typename Ops, typename V = typename Ops::V>
SOFTBENCH_LANES_INLINE typename Ops::Mask apart(const LineEnds<V>& e, V m, V low, V high) {
  return (Ops::less(e.low - low * e.low_weight, -m) & Ops::less(e.high - low * e.high_weight, -m))
         | (Ops::greater(e.low - high * e.low_weight, m)
            & Ops::greater(e.high - high * e.high_weight, m));
}

template <typename Ops, typename V = typename Ops::V>
SOFTBENCH_LANES_INLINE V max_abs(const V3<V>& v) {
  return Ops::max(Ops::abs(v.x), Ops::max(Ops::abs(v.y), Ops::abs(v.z)));
}

/// Status (kLane*) of the Ops::kLanes pairs from i on.
template <typename Ops>
SOFTBENCH_LANES_INLINE void classify_lanes(const Columns& a,
                                           const Columns& b,
                                           std::size_t i,
                                           std::uint8_t* status) {
  using V = typename Ops::V;
  using Mask = typename Ops::Mask;
  using P = V3<V>;
  const P p0{Ops::load(a.x0 + i), Ops::load(a.y0 + i), Ops::load(a.z0 + i)};
  const P p1{Ops::load(a.x1 + i), Ops::load(a.y1 + i), Ops::load(a.z1 + i)};
  const P p2{Ops::load(a.x2 + i), Ops::load(a.y2 + i), Ops::load(a.z2 + i)};
  const P q0{Ops::load(b.x0 + i), Ops::load(b.y0 + i), Ops::load(b.z0 + i)};
  const P q1{Ops::load(b.x1 + i), Ops::load(b.y1 + i), Ops::load(b.z1 + i)};
  const P q2{Ops::load(b.x2 + i), Ops::load(b.y2 + i), Ops::load(b.z2 + i)};
  const V zero{};

  // Step 1: B against H.
  const P e1 = sub(p2, p1);
  const P e2 = sub(p0, p1);
  const P normal = cross(e1, e2);
  const P w0 = sub(q0, p1);
  const P w1 = sub(q1, p1);
  const P w2 = sub(q2, p1);
  const V z0 = dot(normal, w0);
  const V z1 = dot(normal, w1);
  const V z2 = dot(normal, w2);
  const V m_a = Ops::max(max_abs<Ops>(e1), max_abs<Ops>(e2));
  const V m_w = Ops::max(max_abs<Ops>(w0), Ops::max(max_abs<Ops>(w1), max_abs<Ops>(w2)));
  const V m = Ops::max(m_a, m_w);
  const Mask in_range = Ops::less(m, zero + kMaxMagnitude);
  const V bound_z = kSideBound * m_a * m_a * m_w + kFloor;
  const Sides<Ops> zs(z0, z1, z2, bound_z);
  const Mask case_b = in_range & zs.one_side;
  const Mask live = in_range & zs.decided & ~case_b;

  // Case (f): Q0 is the vertex alone on its side; L_B's ends by the ratios of |z|, checked
  // against A on V and W.
  const Rotation<Ops> rb(zs.positive[0], zs.positive[1], zs.positive[2]);
  const Mask q_positive = rb.alone(zs.positive[0], zs.positive[1], zs.positive[2]);
  const V az0 = Ops::abs(z0), az1 = Ops::abs(z1), az2 = Ops::abs(z2);
  const V m2 = m * m;
  const V m5 = m2 * m2 * m;
  const P y_axis = cross(normal, e1);
  const LineEnds<V> y =
      line_ends(rb, q_positive, dot(y_axis, w0), dot(y_axis, w1), dot(y_axis, w2), az0, az1, az2);
  const Mask apart_v =
      apart<Ops>(y, kCrossingMarginY * m5 * m2 + kFloor, zero, dot(normal, normal));
  const V xa = dot(e1, e2);
  const LineEnds<V> x =
      line_ends(rb, q_positive, dot(e1, w0), dot(e1, w1), dot(e1, w2), az0, az1, az2);
  const Mask apart_w =
      apart<Ops>(x, kCrossingMarginX * m5 + kFloor, Ops::min(zero, xa), Ops::max(dot(e1, e1), xa));
  const Mask rejected_vw = apart_v | apart_w;

  // A against B's plane (the clipping signs).
  const P normal_b = cross(sub(q1, q0), sub(q2, q0));
  const V d0 = dot(normal_b, sub(p0, q0));
  const V d1 = dot(normal_b, sub(p1, q0));
  const V d2 = dot(normal_b, sub(p2, q0));
  const V bound_d = kSideBound * (4.0 * m_w * m_w) * (m_a + m_w) + kFloor;
  const Sides<Ops> ds(d0, d1, d2, bound_d);
  const Mask d_one_side = ds.one_side;
  const Mask d_decided = ds.decided;
  const Rotation<Ops> ra(ds.positive[0], ds.positive[1], ds.positive[2]);
  const Mask a_positive = ra.alone(ds.positive[0], ds.positive[1], ds.positive[2]);

  // Ordering on the line, lambda = D . (x - P1): the chord's ends (the next vertex's edge is the
  // upper end when A's apex is on B's positive side) and L_B's (the opposite rule).
  const P direction = cross(normal, normal_b);
  const LineEnds<V> chord = line_ends(ra, a_positive, dot(direction, e2), zero, dot(direction, e1),
                                      Ops::abs(d0), Ops::abs(d1), Ops::abs(d2));
  const LineEnds<V> lb = line_ends(rb, Mask(~q_positive), dot(direction, w0), dot(direction, w1),
                                   dot(direction, w2), az0, az1, az2);
  const V before = lb.high * chord.low_weight - chord.low * lb.high_weight;
  const V after = lb.low * chord.high_weight - chord.high * lb.low_weight;
  const V margin = kOrderMargin * (m5 * m5 * m) + kFloor;
  const Mask ordered =
      Ops::greater(Ops::abs(before), margin) & Ops::greater(Ops::abs(after), margin);
  const Mask separated = Ops::less(before, zero) | Ops::greater(after, zero);

  const Mask clipping = live & ~rejected_vw & ~d_one_side & d_decided & ordered;
  const Mask disjoint =
      case_b | (live & rejected_vw) | (live & d_one_side) | (clipping & separated);
  const Mask intersect = clipping & ~separated;
  for (std::size_t l = 0; l < Ops::kLanes; ++l) {
    status[l] = Ops::lane(disjoint, l)
                    ? kLaneDisjoint
                    : (Ops::lane(intersect, l) ? kLaneIntersect : kLaneUndecided);
  }
}

/// The lane loop over pairs [0, count), count a multiple of Ops::kLanes.
template <typename Ops>
SOFTBENCH_LANES_INLINE void classify_all(const Columns& a,
                                         const Columns& b,
                                         std::size_t count,
                                         std::uint8_t* status) {
  for (std::size_t i = 0; i < count; i += Ops::kLanes) {
    classify_lanes<Ops>(a, b, i, status + i);
  }
}

}  // namespace
}  // namespace softbench::collision::detail
