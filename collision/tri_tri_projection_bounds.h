// SPDX-License-Identifier: MIT
#pragma once

// Error bounds of the projection test's floating-point decisions, shared by the scalar test
// (collision/tri_tri_projection.cpp) and its batched lanes (collision/tri_tri_batch.cpp), which
// must certify exactly the same decisions. Internal to collision/tri_tri_*.cpp.
//
// All coordinates are taken relative to P1 (or Q0); M is the largest absolute component of the
// differences involved, so every quantity is bounded a priori by a polynomial in M: |N|, |y*|
// and the z*, y*, x* coordinates are below 2 M^2, 4 M^3, 6 M^3, 12 M^4 and 3 M^2. A rounded
// operation errs by at most u times the sum of its terms' magnitudes; summing the first-order
// terms of each compared expression gives the figures quoted below, and each bound is a few times
// larger. Beyond kMaxMagnitude products may overflow and below the underflow floor they may
// underflow: there the bounds decide nothing and the exact path does.

#include <limits>

namespace softbench::collision::detail {

/// Unit roundoff 2^-53, and the underflow floor below which no bound decides anything (the same
/// values as kUnitRoundoff and kUnderflowFloor of collision/exact_predicates.h; this header stays
/// free of other includes for the AVX-512 kernel's translation unit).
inline constexpr double kU = std::numeric_limits<double>::epsilon() / 2.0;
inline constexpr double kFloor = 1e-280;
/// orient3d with max-norm permanents: |fl(N . w) - N . w| <= (7 + 56u) u permanent (Shewchuk)
/// and the permanent is at most 6 max|e1, e2|^2 max|w|; 48 > 42 covers the rounding of the
/// bound itself and of the max norms.
inline constexpr double kSideBound = 48.0 * kU;
/// W: an L_B end (|z_b| x_a + |z_a| x_b) / (|z_a| + |z_b|) against A's extent c, compared as
/// N_x - c S: error below ~1150 u M^5. A vertex on H (S = 1): below ~40 u M^2.
inline constexpr double kCrossingMarginX = 4096.0 * kU;
inline constexpr double kVertexMarginX = 128.0 * kU;
/// V: the same with y* (degree 4): below ~6300 u M^7 and ~290 u M^4.
inline constexpr double kCrossingMarginY = 32768.0 * kU;
inline constexpr double kVertexMarginY = 1024.0 * kU;
/// Ordering of chord and L_B ends on the line, lambda = (N_A x N_B) . (x - P1), compared
/// cross-multiplied: terms below 2.2e5 M^11 through a few dozen roundings, error below
/// ~1e-9 M^11; the margin 2^-24 M^11 (6e-8) leaves a factor of about 60.
inline constexpr double kOrderMargin = 0x1p-24;
/// Above this M, degree-3 values may overflow (6 M^3 < 2^993).
inline constexpr double kMaxMagnitude = 0x1p330;

}  // namespace softbench::collision::detail
