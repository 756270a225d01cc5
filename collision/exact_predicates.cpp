// SPDX-License-Identifier: MIT
#include "collision/exact_predicates.h"

#include "collision/expansion_arithmetic.h"

#include <algorithm>
#include <array>
#include <cassert>
#include <cmath>
#include <cstdint>
#include <span>

namespace softbench::collision {
namespace {

// Per thread: an atomic increment costs more than the exact evaluation of a short expansion.
thread_local std::uint64_t orient3d_fallbacks = 0;
thread_local std::uint64_t orient2d_fallbacks = 0;

// ------------------------------------------------------------------------------------------
// Range: the expansion path is exact when every product stays clear of underflow and overflow.
// Scaling the input by a power of two (exact) leaves the sign unchanged; after it the largest
// coordinate is about 2^kTop and every coordinate is a multiple of 2^lsb. A degree-n determinant
// then has all its expansion components on the grid 2^(n lsb), exact while n lsb >= -1074, and
// stays below 2^(n kTop + 3), far from overflow.

struct Range {
  bool any_nonzero = false;
  int top_exponent = 0;  // frexp exponent of the largest |value|
  int lowest_lsb = 0;    // exponent of the least significant mantissa bit of any value
};

template <std::size_t N>
Range range_of(const std::array<double, N>& values) {
  Range range;
  for (const double v : values) {
    assert(std::isfinite(v));
    if (v == 0.0) {
      continue;
    }
    int exponent = 0;
    std::frexp(v, &exponent);  // v = f 2^exponent, 0.5 <= |f| < 1
    const int lsb = exponent - 53;
    range.top_exponent = range.any_nonzero ? std::max(range.top_exponent, exponent) : exponent;
    range.lowest_lsb = range.any_nonzero ? std::min(range.lowest_lsb, lsb) : lsb;
    range.any_nonzero = true;
  }
  return range;
}

/// Scales `values` by 2^(top - top_exponent) when the degree-`degree` determinant stays on a
/// representable grid afterwards; false (values untouched) when the input's exponents span too
/// much for double expansions.
/// Inputs within [2^-280, 2^300] in magnitude (or zero) need no scaling: their mantissa bits
/// lie above 2^-333, so degree-3 products stay above 2^-999, and below 2^903.
template <std::size_t N>
bool in_safe_range(const std::array<double, N>& values) {
  bool safe = true;
  for (const double v : values) {
    const double magnitude = std::abs(v);
    safe &= (magnitude <= 0x1p300) & ((magnitude >= 0x1p-280) | (magnitude == 0.0));
  }
  return safe;
}

template <std::size_t N>
bool scale_for_expansions(std::array<double, N>& values, int degree, int top) {
  if (in_safe_range(values)) {
    return true;
  }
  const Range range = range_of(values);
  if (!range.any_nonzero) {
    return true;
  }
  const int shift = top - range.top_exponent;
  if (degree * (range.lowest_lsb + shift) < -1074) {
    return false;
  }
  for (double& v : values) {
    v = std::ldexp(v, shift);
  }
  return true;
}

/// Largest coordinate after scaling, per degree: |det| < 6 (2^(top + 1))^3 for orient3d and
/// 2 (2^(top + 1))^2 for orient2d, both below 2^1000; the grid condition above then allows
/// exponent spans of about 600 (orient3d) and 930 (orient2d) binary orders.
constexpr int kOrient3dTop = 300;
constexpr int kOrient2dTop = 450;

// ------------------------------------------------------------------------------------------
// Expansion determinants. Coordinate differences are two-component expansions (two_diff), so
// the determinant is the exact polynomial of the input; zero elimination keeps the common case
// of exactly representable differences short (the designed pairs' sizes are a few components).

struct Difference {
  std::array<double, 2> c{};
  std::size_t n = 1;
  std::span<const double> span() const { return {c.data(), n}; }
};

Difference difference(double a, double b) {
  Difference d;
  double head = 0.0;
  double tail = 0.0;
  expansion::two_diff(a, b, head, tail);
  if (tail != 0.0) {
    d.c = {tail, head};
    d.n = 2;
  } else {
    d.c = {head, 0.0};
  }
  return d;
}

/// u_i v_j - u_j v_i for two-component u and v: at most 16 components.
template <bool kFma>
std::size_t cross_component(const Difference& ui,
                            const Difference& vj,
                            const Difference& uj,
                            const Difference& vi,
                            std::span<double> out) {
  std::array<double, 8> left;
  std::array<double, 8> right;
  std::array<double, 8> scratch;
  const std::size_t nl = expansion::product<kFma>(ui.span(), vj.span(), left, scratch);
  const std::size_t nr = expansion::product<kFma>(uj.span(), vi.span(), right, scratch);
  expansion::negate(std::span<double>(right.data(), nr));
  return expansion::sum(std::span<const double>(left.data(), nl),
                        std::span<const double>(right.data(), nr), out);
}

/// Floating-point evaluation that also accumulates the magnitude of every rounding error
/// (the tails of the error-free transformations): when the sum of those is zero, every
/// operation was exact and so is the result. Designed and snapped data with short binary
/// coordinates (integers, halves, grid points) are decided here at the cost of about two double
/// evaluations; anything else goes on to the expansions.
template <bool kFma>
struct Checked {
  double error = 0.0;  // sum of |tail| over all operations so far

  /// x = fl(a op b) through an error-free transformation, accumulating its tail.
  template <void (*kTransform)(double, double, double&, double&)>
  double apply(double a, double b) {
    double x = 0.0;
    double y = 0.0;
    kTransform(a, b, x, y);
    error += std::abs(y);
    return x;
  }
  double diff(double a, double b) { return apply<expansion::two_diff>(a, b); }
  double sum(double a, double b) { return apply<expansion::two_sum>(a, b); }
  double product(double a, double b) { return apply<expansion::two_product<kFma>>(a, b); }
};

int sign_of(double x) {
  return x > 0.0 ? 1 : (x < 0.0 ? -1 : 0);
}

/// Exact sign of det[b - a, c - a, d - a] from the scaled coordinates a, b, c, d (xyz each).
template <bool kFma>
int orient3d_expansion(const std::array<double, 12>& v) {
  {
    Checked<kFma> c;
    std::array<double, 9> d;  // rows b - a, c - a, d - a
    for (std::size_t row = 0; row < 3; ++row) {
      for (std::size_t k = 0; k < 3; ++k) {
        d[3 * row + k] = c.diff(v[3 * (row + 1) + k], v[k]);
      }
    }
    double det = 0.0;
    for (std::size_t k = 0; k < 3; ++k) {
      const std::size_t i = (k + 1) % 3;
      const std::size_t j = (k + 2) % 3;
      const double minor = c.diff(c.product(d[i], d[3 + j]), c.product(d[j], d[3 + i]));
      det = c.sum(det, c.product(minor, d[6 + k]));
    }
    if (c.error == 0.0) {
      return sign_of(det);
    }
  }
  std::array<Difference, 9> d;  // rows b - a, c - a, d - a
  for (std::size_t row = 0; row < 3; ++row) {
    for (std::size_t k = 0; k < 3; ++k) {
      d[3 * row + k] = difference(v[3 * (row + 1) + k], v[k]);
    }
  }
  std::array<double, 192> total;
  std::array<double, 192> scratch;
  std::size_t length = 0;
  for (std::size_t k = 0; k < 3; ++k) {
    const std::size_t i = (k + 1) % 3;
    const std::size_t j = (k + 2) % 3;
    std::array<double, 16> minor;
    std::array<double, 64> term;
    std::array<double, 64> term_scratch;
    const std::size_t nm = cross_component<kFma>(d[i], d[3 + j], d[j], d[3 + i], minor);
    const std::size_t nt = expansion::product<kFma>(std::span<const double>(minor.data(), nm),
                                                    d[6 + k].span(), term, term_scratch);
    if (length == 0) {
      std::copy_n(term.begin(), nt, total.begin());
      length = nt;
      continue;
    }
    std::copy_n(total.begin(), length, scratch.begin());
    length = expansion::sum(std::span<const double>(scratch.data(), length),
                            std::span<const double>(term.data(), nt), total);
  }
  return expansion::sign(std::span<const double>(total.data(), length));
}

/// Exact sign of (bx - ax)(cy - ay) - (by - ay)(cx - ax) from scaled coordinates.
template <bool kFma>
int orient2d_expansion(const std::array<double, 6>& v) {
  {
    Checked<kFma> c;
    const double det = c.diff(c.product(c.diff(v[2], v[0]), c.diff(v[5], v[1])),
                              c.product(c.diff(v[3], v[1]), c.diff(v[4], v[0])));
    if (c.error == 0.0) {
      return sign_of(det);
    }
  }
  const Difference bx = difference(v[2], v[0]);
  const Difference by = difference(v[3], v[1]);
  const Difference cx = difference(v[4], v[0]);
  const Difference cy = difference(v[5], v[1]);
  std::array<double, 16> det;
  const std::size_t n = cross_component<kFma>(bx, cy, by, cx, det);
  return expansion::sign(std::span<const double>(det.data(), n));
}

#if defined(__x86_64__) || defined(__i386__)
// The FMA variants: the whole expansion computation inlined into a function compiled for FMA,
// chosen at run time (the project builds for baseline x86-64).
__attribute__((target("fma"), flatten)) int orient3d_fma(const std::array<double, 12>& v) {
  return orient3d_expansion<true>(v);
}
__attribute__((target("fma"), flatten)) int orient2d_fma(const std::array<double, 6>& v) {
  return orient2d_expansion<true>(v);
}
bool cpu_has_fma() {
  static const bool has_fma = __builtin_cpu_supports("fma");
  return has_fma;
}
#else
int orient3d_fma(const std::array<double, 12>& v) {
  return orient3d_expansion<false>(v);
}
int orient2d_fma(const std::array<double, 6>& v) {
  return orient2d_expansion<false>(v);
}
bool cpu_has_fma() {
  return false;
}
#endif

// ------------------------------------------------------------------------------------------
// Wide integers: the fallback for inputs whose exponents span more than the expansions allow
// (e.g. 1e-200 next to 1). Every double is m 2^e with an integer m of at most 53 bits, so after
// dividing by the smallest 2^e all coordinates are integers below 2^2152 and the determinant an
// integer below 2^6460: schoolbook arithmetic on 32-bit limbs, slow and never on a hot path.

class WideInteger {
 public:
  static constexpr std::size_t kLimbs = 216;

  /// m 2^shift (|m| < 2^63, 0 <= shift).
  static WideInteger shifted(std::int64_t m, int shift) {
    WideInteger r;
    r.negative_ = m < 0;
    std::uint64_t magnitude =
        m < 0 ? 0 - static_cast<std::uint64_t>(m) : static_cast<std::uint64_t>(m);
    const auto limb_shift = static_cast<std::size_t>(shift / 32);
    const int bit_shift = shift % 32;
    assert(limb_shift + 4 <= kLimbs);
    // Up to 63 + 31 bits: three limbs.
    const std::uint64_t low = magnitude << bit_shift;
    const std::uint64_t high = bit_shift == 0 ? 0 : magnitude >> (64 - bit_shift);
    r.limb_[limb_shift] = static_cast<std::uint32_t>(low);
    r.limb_[limb_shift + 1] = static_cast<std::uint32_t>(low >> 32);
    r.limb_[limb_shift + 2] = static_cast<std::uint32_t>(high);
    r.size_ = limb_shift + 3;
    r.trim();
    return r;
  }

  int sign() const { return size_ == 0 ? 0 : (negative_ ? -1 : 1); }

  friend WideInteger operator-(const WideInteger& a, WideInteger b) {
    b.negative_ = !b.negative_;
    return a + b;
  }

  friend WideInteger operator+(const WideInteger& a, const WideInteger& b) {
    if (a.negative_ == b.negative_) {
      WideInteger r = add_magnitudes(a, b);
      r.negative_ = a.negative_;
      r.trim();
      return r;
    }
    const bool a_larger = compare_magnitudes(a, b) >= 0;
    WideInteger r = a_larger ? subtract_magnitudes(a, b) : subtract_magnitudes(b, a);
    r.negative_ = a_larger ? a.negative_ : b.negative_;
    r.trim();
    return r;
  }

  friend WideInteger operator*(const WideInteger& a, const WideInteger& b) {
    WideInteger r;
    assert(a.size_ + b.size_ <= kLimbs);
    for (std::size_t i = 0; i < a.size_; ++i) {
      std::uint64_t carry = 0;
      for (std::size_t j = 0; j < b.size_; ++j) {
        const std::uint64_t t =
            static_cast<std::uint64_t>(a.limb_[i]) * b.limb_[j] + r.limb_[i + j] + carry;
        r.limb_[i + j] = static_cast<std::uint32_t>(t);
        carry = t >> 32;
      }
      r.limb_[i + b.size_] = static_cast<std::uint32_t>(carry);
    }
    r.size_ = a.size_ + b.size_;
    r.negative_ = a.negative_ != b.negative_;
    r.trim();
    return r;
  }

 private:
  void trim() {
    while (size_ > 0 && limb_[size_ - 1] == 0) {
      --size_;
    }
    negative_ = negative_ && size_ > 0;
  }

  static int compare_magnitudes(const WideInteger& a, const WideInteger& b) {
    if (a.size_ != b.size_) {
      return a.size_ > b.size_ ? 1 : -1;
    }
    for (std::size_t i = a.size_; i-- > 0;) {
      if (a.limb_[i] != b.limb_[i]) {
        return a.limb_[i] > b.limb_[i] ? 1 : -1;
      }
    }
    return 0;
  }

  static WideInteger add_magnitudes(const WideInteger& a, const WideInteger& b) {
    WideInteger r;
    const std::size_t n = std::max(a.size_, b.size_);
    assert(n < kLimbs);
    std::uint64_t carry = 0;
    for (std::size_t i = 0; i < n; ++i) {
      const std::uint64_t t = static_cast<std::uint64_t>(a.limb_[i]) + b.limb_[i] + carry;
      r.limb_[i] = static_cast<std::uint32_t>(t);
      carry = t >> 32;
    }
    r.limb_[n] = static_cast<std::uint32_t>(carry);
    r.size_ = n + 1;
    return r;
  }

  /// |a| - |b| for |a| >= |b|.
  static WideInteger subtract_magnitudes(const WideInteger& a, const WideInteger& b) {
    WideInteger r;
    std::int64_t borrow = 0;
    for (std::size_t i = 0; i < a.size_; ++i) {
      std::int64_t t = static_cast<std::int64_t>(a.limb_[i]) - b.limb_[i] - borrow;
      borrow = t < 0 ? 1 : 0;
      t += borrow << 32;
      r.limb_[i] = static_cast<std::uint32_t>(t);
    }
    r.size_ = a.size_;
    return r;
  }

  bool negative_ = false;
  std::size_t size_ = 0;  // limbs in use; no leading zero limb
  std::array<std::uint32_t, kLimbs> limb_{};
};

/// The input as wide integers on one common scale 2^lowest_lsb.
template <std::size_t N>
std::array<WideInteger, N> to_wide_integers(const std::array<double, N>& values) {
  const Range range = range_of(values);
  std::array<WideInteger, N> out;
  for (std::size_t i = 0; i < N; ++i) {
    if (values[i] == 0.0) {
      continue;
    }
    int exponent = 0;
    const double fraction = std::frexp(values[i], &exponent);
    const auto mantissa = static_cast<std::int64_t>(std::ldexp(fraction, 53));  // exact
    out[i] = WideInteger::shifted(mantissa, exponent - 53 - range.lowest_lsb);
  }
  return out;
}

int orient3d_wide(const std::array<double, 12>& values) {
  const std::array<WideInteger, 12> v = to_wide_integers(values);
  auto d = [&](std::size_t row, std::size_t k) { return v[3 * row + k] - v[k]; };
  WideInteger det;
  for (std::size_t k = 0; k < 3; ++k) {
    const std::size_t i = (k + 1) % 3;
    const std::size_t j = (k + 2) % 3;
    det = det + (d(1, i) * d(2, j) - d(1, j) * d(2, i)) * d(3, k);
  }
  return det.sign();
}

int orient2d_wide(const std::array<double, 6>& values) {
  const std::array<WideInteger, 6> v = to_wide_integers(values);
  return ((v[2] - v[0]) * (v[5] - v[1]) - (v[3] - v[1]) * (v[4] - v[0])).sign();
}

}  // namespace

namespace detail {
void count_orient3d_fallback() {
  ++orient3d_fallbacks;
}
void count_orient2d_fallback() {
  ++orient2d_fallbacks;
}
}  // namespace detail

namespace {

/// Which exact path: expansions with the CPU's best product (wide integers when the exponents
/// span too much), expansions with Dekker's product, or wide integers regardless.
enum class ExactPath : std::uint8_t { kBest, kWithoutFma, kWide };

int orient3d_by(ExactPath path,
                const Eigen::Vector3d& a,
                const Eigen::Vector3d& b,
                const Eigen::Vector3d& c,
                const Eigen::Vector3d& d) {
  std::array<double, 12> v = {a.x(), a.y(), a.z(), b.x(), b.y(), b.z(),
                              c.x(), c.y(), c.z(), d.x(), d.y(), d.z()};
  if (path == ExactPath::kWide || !scale_for_expansions(v, 3, kOrient3dTop)) {
    return orient3d_wide(v);
  }
  return path == ExactPath::kBest && cpu_has_fma() ? orient3d_fma(v) : orient3d_expansion<false>(v);
}

}  // namespace

int orient3d_exact(const Eigen::Vector3d& a,
                   const Eigen::Vector3d& b,
                   const Eigen::Vector3d& c,
                   const Eigen::Vector3d& d) {
  return orient3d_by(ExactPath::kBest, a, b, c, d);
}

int orient2d_exact(double ax, double ay, double bx, double by, double cx, double cy) {
  std::array<double, 6> v = {ax, ay, bx, by, cx, cy};
  if (!scale_for_expansions(v, 2, kOrient2dTop)) {
    return orient2d_wide(v);
  }
  return cpu_has_fma() ? orient2d_fma(v) : orient2d_expansion<false>(v);
}

namespace detail {
int orient3d_exact_without_fma(const Eigen::Vector3d& a,
                               const Eigen::Vector3d& b,
                               const Eigen::Vector3d& c,
                               const Eigen::Vector3d& d) {
  return orient3d_by(ExactPath::kWithoutFma, a, b, c, d);
}
int orient3d_exact_wide(const Eigen::Vector3d& a,
                        const Eigen::Vector3d& b,
                        const Eigen::Vector3d& c,
                        const Eigen::Vector3d& d) {
  return orient3d_by(ExactPath::kWide, a, b, c, d);
}
}  // namespace detail

PredicateStats predicate_stats() {
  return {orient3d_fallbacks, orient2d_fallbacks};
}

void reset_predicate_stats() {
  orient3d_fallbacks = 0;
  orient2d_fallbacks = 0;
}

}  // namespace softbench::collision
