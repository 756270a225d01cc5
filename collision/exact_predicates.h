// SPDX-License-Identifier: MIT
#pragma once

// Filtered exact orientation predicates for the triangle-triangle tests.
//
// Each predicate first evaluates its determinant in double and compares it with Shewchuk's
// stage-A error bound (J. R. Shewchuk, "Adaptive precision floating-point arithmetic and fast
// robust geometric predicates", DCG 18, 1997, section 4): when |det| exceeds the bound its sign
// is the exact sign. Otherwise the determinant is recomputed exactly with floating-point
// expansions (collision/expansion_arithmetic.h): the input is scaled by a power of two so that
// no product underflows or overflows, coordinate differences become two-component expansions and
// the determinant a short expansion whose largest component has the exact sign. That costs tens
// of nanoseconds when the differences are exact (typical of designed and snapped data) and a few
// hundred otherwise. Inputs whose exponents span more than about 600 binary orders within one
// call (e.g. 1e-200 next to 1) take a slower wide-integer path instead, so the answer is exact
// for every finite input.
//
// The bound assumes no underflow; an absolute floor (kUnderflowFloor) sends determinants too
// small to trust to the exact path as well.

#include <Eigen/Core>

#include <cmath>
#include <cstdint>
#include <limits>

namespace softbench::collision {

/// Unit roundoff of double, 2^-53.
inline constexpr double kUnitRoundoff = std::numeric_limits<double>::epsilon() / 2.0;
/// Shewchuk's ccwerrboundA: |det - orient2d| <= this * (|detleft| + |detright|).
inline constexpr double kOrient2dErrorBound = (3.0 + 16.0 * kUnitRoundoff) * kUnitRoundoff;
/// Shewchuk's o3derrboundA: |det - orient3d| <= this * permanent.
inline constexpr double kOrient3dErrorBound = (7.0 + 56.0 * kUnitRoundoff) * kUnitRoundoff;
/// Below this a filtered determinant may have lost bits to underflow: decide it exactly.
inline constexpr double kUnderflowFloor = 1e-280;

/// The signature of orient3d and its exact variants.
using Orient3dFunction = int(const Eigen::Vector3d& a,
                             const Eigen::Vector3d& b,
                             const Eigen::Vector3d& c,
                             const Eigen::Vector3d& d);

/// Exact sign of det[b - a, c - a, d - a] = ((b - a) x (c - a)) . (d - a): +1 when d lies on the
/// side of the plane (a, b, c) that its normal (b - a) x (c - a) points to, 0 when coplanar.
Orient3dFunction orient3d_exact;

/// Exact sign of (bx - ax)(cy - ay) - (by - ay)(cx - ax): +1 for a counter-clockwise a, b, c.
int orient2d_exact(double ax, double ay, double bx, double by, double cx, double cy);

/// Decides the sign of a determinant `det` computed in double whose error is at most `bound`;
/// calls `exact()` when it cannot. Shared by the predicates below and by callers that compute
/// the determinant themselves (the projection test reuses the normal of triangle A).
template <typename Exact>
inline int filtered_sign(double det, double bound, Exact&& exact) {
  const double safe_bound = bound + kUnderflowFloor;
  if (det > safe_bound) {
    return 1;
  }
  if (det < -safe_bound) {
    return -1;
  }
  return exact();
}

namespace detail {
void count_orient3d_fallback();
void count_orient2d_fallback();
/// The exact paths by name, for tests: expansions with Dekker's product (no FMA), and the wide
/// integers.
Orient3dFunction orient3d_exact_without_fma;
Orient3dFunction orient3d_exact_wide;
}  // namespace detail

/// Filtered exact orient3d (see orient3d_exact for the sign convention).
inline int orient3d(const Eigen::Vector3d& a,
                    const Eigen::Vector3d& b,
                    const Eigen::Vector3d& c,
                    const Eigen::Vector3d& d) {
  const Eigen::Vector3d u = b - a;
  const Eigen::Vector3d v = c - a;
  const Eigen::Vector3d w = d - a;
  const double nx = u.y() * v.z() - u.z() * v.y();
  const double ny = u.z() * v.x() - u.x() * v.z();
  const double nz = u.x() * v.y() - u.y() * v.x();
  const double det = nx * w.x() + ny * w.y() + nz * w.z();
  const double permanent = (std::abs(u.y() * v.z()) + std::abs(u.z() * v.y())) * std::abs(w.x())
                           + (std::abs(u.z() * v.x()) + std::abs(u.x() * v.z())) * std::abs(w.y())
                           + (std::abs(u.x() * v.y()) + std::abs(u.y() * v.x())) * std::abs(w.z());
  return filtered_sign(det, kOrient3dErrorBound * permanent, [&] {
    detail::count_orient3d_fallback();
    return orient3d_exact(a, b, c, d);
  });
}

/// Filtered exact orient2d (see orient2d_exact for the sign convention).
inline int orient2d(double ax, double ay, double bx, double by, double cx, double cy) {
  const double left = (bx - ax) * (cy - ay);
  const double right = (by - ay) * (cx - ax);
  return filtered_sign(left - right, kOrient2dErrorBound * (std::abs(left) + std::abs(right)), [&] {
    detail::count_orient2d_fallback();
    return orient2d_exact(ax, ay, bx, by, cx, cy);
  });
}

/// How often the filters above could not decide, on the calling thread (for reports).
struct PredicateStats {
  std::uint64_t orient3d_fallbacks = 0;
  std::uint64_t orient2d_fallbacks = 0;
};
/// The calling thread's counts, and their reset.
PredicateStats predicate_stats();
void reset_predicate_stats();

}  // namespace softbench::collision
