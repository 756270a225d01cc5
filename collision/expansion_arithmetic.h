// SPDX-License-Identifier: MIT
#pragma once

// Exact floating-point expansion arithmetic after J. R. Shewchuk, "Adaptive precision
// floating-point arithmetic and fast robust geometric predicates", DCG 18, 1997 (section 2): a
// number is held exactly as a sum of doubles ("components") that do not overlap, stored from the
// smallest magnitude to the largest, with zero components eliminated. Sums and products of
// expansions are exact as long as no intermediate product underflows or overflows; the callers
// (collision/exact_predicates.cpp) scale their input by a power of two to guarantee that.
//
// The error-free transformations need round-to-nearest double arithmetic evaluated as written:
// no x87 excess precision and no contraction of a * b + c into a fused multiply-add behind the
// code's back (collision/CMakeLists.txt compiles the user of this header with
// -ffp-contract=off). two_product uses an explicit FMA when the caller instantiates it with
// kFma = true (on a CPU that has one) and Dekker's splitting otherwise.

#include <algorithm>
#include <cassert>
#include <cmath>
#include <cstddef>
#include <span>

namespace softbench::collision::expansion {

/// x + y == a + b exactly, x = fl(a + b) (Knuth's two-sum, no precondition).
inline void two_sum(double a, double b, double& x, double& y) {
  x = a + b;
  const double b_virtual = x - a;
  const double a_virtual = x - b_virtual;
  y = (a - a_virtual) + (b - b_virtual);
}

/// x + y == a - b exactly, x = fl(a - b).
inline void two_diff(double a, double b, double& x, double& y) {
  x = a - b;
  const double b_virtual = a - x;
  const double a_virtual = x + b_virtual;
  y = (a - a_virtual) + (b_virtual - b);
}

/// x + y == a + b exactly when |a| >= |b| or a == 0 (Dekker's fast two-sum).
inline void fast_two_sum(double a, double b, double& x, double& y) {
  x = a + b;
  y = b - (x - a);
}

/// x + y == a * b exactly, x = fl(a * b) (no underflow; |a|, |b| < 2^996 for Dekker's split).
template <bool kFma>
inline void two_product(double a, double b, double& x, double& y) {
  x = a * b;
  if constexpr (kFma) {
    y = std::fma(a, b, -x);
  } else {
    constexpr double kSplitter = 134217729.0;  // 2^27 + 1: splits 53 bits into 26 + 26
    const double ca = kSplitter * a;
    const double a_high = ca - (ca - a);
    const double a_low = a - a_high;
    const double cb = kSplitter * b;
    const double b_high = cb - (cb - b);
    const double b_low = b - b_high;
    const double error = ((x - a_high * b_high) - a_low * b_high) - a_high * b_low;
    y = a_low * b_low - error;
  }
}

/// h = e + f (Shewchuk's fast_expansion_sum_zeroelim). e and f are non-empty; h has room for
/// e.size() + f.size() components. Returns h's length (at least 1; a zero value is {0}).
inline std::size_t sum(std::span<const double> e, std::span<const double> f, std::span<double> h) {
  assert(!e.empty() && !f.empty() && h.size() >= e.size() + f.size());
  std::size_t ei = 0;
  std::size_t fi = 0;
  std::size_t hi = 0;
  // Merge by magnitude: take the next smaller component of either expansion.
  auto take = [&]() {
    if (fi == f.size() || (ei < e.size() && (f[fi] > e[ei]) == (f[fi] > -e[ei]))) {
      return e[ei++];
    }
    return f[fi++];
  };
  double q = take();
  double x = 0.0;
  double y = 0.0;
  if (ei < e.size() || fi < f.size()) {
    fast_two_sum(take(), q, x, y);
    q = x;
    if (y != 0.0) {
      h[hi++] = y;
    }
  }
  while (ei < e.size() || fi < f.size()) {
    two_sum(q, take(), x, y);
    q = x;
    if (y != 0.0) {
      h[hi++] = y;
    }
  }
  if (q != 0.0 || hi == 0) {
    h[hi++] = q;
  }
  return hi;
}

/// h = b * e (Shewchuk's scale_expansion_zeroelim); h has room for 2 e.size() components.
template <bool kFma>
inline std::size_t scale(std::span<const double> e, double b, std::span<double> h) {
  assert(!e.empty() && h.size() >= 2 * e.size());
  std::size_t hi = 0;
  double q = 0.0;
  double low = 0.0;
  two_product<kFma>(e[0], b, q, low);
  if (low != 0.0) {
    h[hi++] = low;
  }
  for (std::size_t i = 1; i < e.size(); ++i) {
    double high = 0.0;
    two_product<kFma>(e[i], b, high, low);
    double s = 0.0;
    double y = 0.0;
    two_sum(q, low, s, y);
    if (y != 0.0) {
      h[hi++] = y;
    }
    fast_two_sum(high, s, q, y);
    if (y != 0.0) {
      h[hi++] = y;
    }
  }
  if (q != 0.0 || hi == 0) {
    h[hi++] = q;
  }
  return hi;
}

/// h = -e in place.
inline void negate(std::span<double> e) {
  for (double& c : e) {
    c = -c;
  }
}

/// h = e * f, by scaling e with each component of f and summing; `scratch` and h each have room
/// for 2 e.size() f.size() components.
template <bool kFma>
inline std::size_t product(std::span<const double> e,
                           std::span<const double> f,
                           std::span<double> h,
                           std::span<double> scratch) {
  assert(h.size() >= 2 * e.size() * f.size() && scratch.size() >= h.size());
  std::size_t length = scale<kFma>(e, f[0], h);
  for (std::size_t j = 1; j < f.size(); ++j) {
    double term[2 * 64];  // e is at most 64 components long in this project's predicates
    assert(e.size() <= 64);
    const std::size_t term_length = scale<kFma>(e, f[j], term);
    std::copy_n(h.begin(), length, scratch.begin());
    length = sum(scratch.first(length), std::span<const double>(term, term_length), h);
  }
  return length;
}

/// Sign of a zero-eliminated expansion: that of its largest (last) component.
inline int sign(std::span<const double> e) {
  const double top = e.back();
  return top > 0.0 ? 1 : (top < 0.0 ? -1 : 0);
}

}  // namespace softbench::collision::expansion
