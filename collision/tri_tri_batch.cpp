// SPDX-License-Identifier: MIT
#include "collision/tri_tri_batch.h"

#include "collision/exact_predicates.h"
#include "collision/tri_tri_projection.h"

#include <algorithm>
#include <cassert>
#include <cmath>
#include <limits>

namespace softbench::collision {
namespace {

constexpr std::size_t kLanes = 8;
constexpr int kDisjoint = 0;
constexpr int kIntersect = 1;
constexpr int kUndecided = 2;
constexpr double kInfinity = std::numeric_limits<double>::infinity();
/// Rounding of a projected vertex D . x relative to |D| max|x|: a dot product of rounded
/// cross products, a few dozen ulps; 256 leaves a wide margin.
constexpr double kProjectionError = 256.0 * kUnitRoundoff;
/// Planes closer to parallel than sin(angle) = 1e-6 go to the exact path (the interval ends
/// are ill-conditioned there).
constexpr double kMinSineSquared = 1e-12;

struct Lane3 {
  double x, y, z;
};

inline Lane3 sub(Lane3 a, Lane3 b) {
  return {a.x - b.x, a.y - b.y, a.z - b.z};
}
inline Lane3 cross(Lane3 a, Lane3 b) {
  return {a.y * b.z - a.z * b.y, a.z * b.x - a.x * b.z, a.x * b.y - a.y * b.x};
}
inline Lane3 abs_minors(Lane3 a, Lane3 b) {
  return {std::abs(a.y * b.z) + std::abs(a.z * b.y), std::abs(a.z * b.x) + std::abs(a.x * b.z),
          std::abs(a.x * b.y) + std::abs(a.y * b.x)};
}
inline double dot(Lane3 a, Lane3 b) {
  return a.x * b.x + a.y * b.y + a.z * b.z;
}
inline double dot_abs(Lane3 m, Lane3 w) {
  return m.x * std::abs(w.x) + m.y * std::abs(w.y) + m.z * std::abs(w.z);
}

/// One triangle's interval on the line (projected on D), from its vertices' plane distances d
/// with error bounds e: the two edges whose ends have opposite signs cross the plane.
struct Interval {
  double low, high, error;
};

inline Interval interval(const double (&t)[3], const double (&d)[3], const double (&e)[3]) {
  Interval r{kInfinity, -kInfinity, 0.0};
  for (int i = 0; i < 3; ++i) {
    const int j = (i + 1) % 3;
    const bool crosses = (d[i] < 0.0) != (d[j] < 0.0);
    const double sum = std::abs(d[i]) + std::abs(d[j]);
    const double ratio = d[i] / (d[i] - d[j]);
    const double at = t[i] + (t[j] - t[i]) * ratio;
    const double error = 2.0 * std::abs(t[j] - t[i]) * (e[i] + e[j]) / sum;
    r.low = crosses && at < r.low ? at : r.low;
    r.high = crosses && at > r.high ? at : r.high;
    r.error = crosses && error > r.error ? error : r.error;
  }
  return r;
}

/// Raw, non-aliasing views of one SoA (so the compiler may vectorise the lane loop).
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

Columns columns(const TriangleSoA& t, std::size_t begin) {
  return {t.x0.data() + begin, t.y0.data() + begin, t.z0.data() + begin,
          t.x1.data() + begin, t.y1.data() + begin, t.z1.data() + begin,
          t.x2.data() + begin, t.y2.data() + begin, t.z2.data() + begin};
}

inline double max_abs(Lane3 v, double m) {
  const double x = std::abs(v.x);
  const double y = std::abs(v.y);
  const double z = std::abs(v.z);
  const double xy = x > y ? x : y;
  const double xyz = xy > z ? xy : z;
  return xyz > m ? xyz : m;
}

/// Branch-free over kLanes pairs: status[l] = kDisjoint, kIntersect or kUndecided.
__attribute__((target_clones("avx2", "default"))) void classify_block(Columns a,
                                                                      Columns b,
                                                                      int* __restrict status) {
  for (std::size_t l = 0; l < kLanes; ++l) {
    const Lane3 p[3] = {
        {a.x0[l], a.y0[l], a.z0[l]}, {a.x1[l], a.y1[l], a.z1[l]}, {a.x2[l], a.y2[l], a.z2[l]}};
    const Lane3 q[3] = {
        {b.x0[l], b.y0[l], b.z0[l]}, {b.x1[l], b.y1[l], b.z1[l]}, {b.x2[l], b.y2[l], b.z2[l]}};
    // A's plane (origin p1, normal (p2 - p1) x (p0 - p1)) and B's (origin q0).
    const Lane3 ua = sub(p[2], p[1]);
    const Lane3 va = sub(p[0], p[1]);
    const Lane3 na = cross(ua, va);
    const Lane3 ma = abs_minors(ua, va);
    const Lane3 ub = sub(q[1], q[0]);
    const Lane3 vb = sub(q[2], q[0]);
    const Lane3 nb = cross(ub, vb);
    const Lane3 mb = abs_minors(ub, vb);
    double dq[3], eq[3], dp[3], ep[3];
    for (int k = 0; k < 3; ++k) {
      const Lane3 wq = sub(q[k], p[1]);
      dq[k] = dot(na, wq);
      eq[k] = kOrient3dErrorBound * dot_abs(ma, wq) + kUnderflowFloor;
      const Lane3 wp = sub(p[k], q[0]);
      dp[k] = dot(nb, wp);
      ep[k] = kOrient3dErrorBound * dot_abs(mb, wp) + kUnderflowFloor;
    }
    const bool b_above = (dq[0] > eq[0]) & (dq[1] > eq[1]) & (dq[2] > eq[2]);
    const bool b_below = (dq[0] < -eq[0]) & (dq[1] < -eq[1]) & (dq[2] < -eq[2]);
    const bool a_above = (dp[0] > ep[0]) & (dp[1] > ep[1]) & (dp[2] > ep[2]);
    const bool a_below = (dp[0] < -ep[0]) & (dp[1] < -ep[1]) & (dp[2] < -ep[2]);
    const bool reject = b_above | b_below | a_above | a_below;
    const bool signs_certain = (std::abs(dq[0]) > eq[0]) & (std::abs(dq[1]) > eq[1])
                               & (std::abs(dq[2]) > eq[2]) & (std::abs(dp[0]) > ep[0])
                               & (std::abs(dp[1]) > ep[1]) & (std::abs(dp[2]) > ep[2]);
    // Intervals on the line, projected on D = na x nb (any direction along the line keeps the
    // order of its points).
    const Lane3 d = cross(na, nb);
    const double d_norm2 = dot(d, d);
    const bool well_conditioned = d_norm2 > kMinSineSquared * dot(na, na) * dot(nb, nb);
    double tp[3], tq[3];
    double extent = 0.0;
    for (int k = 0; k < 3; ++k) {
      tp[k] = dot(d, p[k]);
      tq[k] = dot(d, q[k]);
      extent = max_abs(q[k], max_abs(p[k], extent));
    }
    const Interval ia = interval(tp, dp, ep);
    const Interval ib = interval(tq, dq, eq);
    const double margin = 8.0 * (ia.error + ib.error)
                          + kProjectionError * (std::abs(d.x) + std::abs(d.y) + std::abs(d.z)) * 3.0
                                * extent;  // L1 >= L2 norm; no sqrt (errno blocks SIMD)
    const bool overlap = (ia.high - ib.low > margin) & (ib.high - ia.low > margin);
    const bool apart = (ib.low - ia.high > margin) | (ia.low - ib.high > margin);
    const bool decided = signs_certain & well_conditioned & (overlap | apart);
    status[l] = reject ? kDisjoint : (decided ? (overlap ? kIntersect : kDisjoint) : kUndecided);
  }
}

}  // namespace

void TriangleSoA::reserve(std::size_t n) {
  for (auto* v : {&x0, &y0, &z0, &x1, &y1, &z1, &x2, &y2, &z2}) {
    v->reserve(n);
  }
}

void TriangleSoA::clear() {
  for (auto* v : {&x0, &y0, &z0, &x1, &y1, &z1, &x2, &y2, &z2}) {
    v->clear();
  }
}

void TriangleSoA::push_back(const Eigen::Vector3d& v0,
                            const Eigen::Vector3d& v1,
                            const Eigen::Vector3d& v2) {
  x0.push_back(v0.x());
  y0.push_back(v0.y());
  z0.push_back(v0.z());
  x1.push_back(v1.x());
  y1.push_back(v1.y());
  z1.push_back(v1.z());
  x2.push_back(v2.x());
  y2.push_back(v2.y());
  z2.push_back(v2.z());
}

Eigen::Vector3d TriangleSoA::vertex(std::size_t i, int k) const {
  switch (k) {
    case 0:
      return {x0[i], y0[i], z0[i]};
    case 1:
      return {x1[i], y1[i], z1[i]};
    default:
      return {x2[i], y2[i], z2[i]};
  }
}

BatchStats tri_tri_batch(const TriangleSoA& a,
                         const TriangleSoA& b,
                         std::span<std::uint8_t> intersect) {
  assert(a.size() == b.size() && intersect.size() >= a.size());
  BatchStats stats;
  stats.pairs = a.size();
  auto exact = [&](std::size_t i) -> std::uint8_t {
    ++stats.exact_fallbacks;
    return tri_tri_projection(a.vertex(i, 0), a.vertex(i, 1), a.vertex(i, 2), b.vertex(i, 0),
                              b.vertex(i, 1), b.vertex(i, 2))
                   .intersect()
               ? 1
               : 0;
  };
  const std::size_t blocks = a.size() / kLanes;
  int status[kLanes];
  for (std::size_t block = 0; block < blocks; ++block) {
    const std::size_t begin = block * kLanes;
    classify_block(columns(a, begin), columns(b, begin), status);
    for (std::size_t l = 0; l < kLanes; ++l) {
      intersect[begin + l] =
          status[l] == kUndecided ? exact(begin + l) : static_cast<std::uint8_t>(status[l]);
    }
  }
  for (std::size_t i = blocks * kLanes; i < a.size(); ++i) {
    intersect[i] = exact(i);
  }
  return stats;
}

}  // namespace softbench::collision
