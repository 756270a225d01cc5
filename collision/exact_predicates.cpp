// SPDX-License-Identifier: MIT
#include "collision/exact_predicates.h"

#include <gmp.h>

#include <algorithm>
#include <array>
#include <atomic>
#include <cassert>
#include <cmath>
#include <cstdint>
#include <span>

namespace softbench::collision {
namespace {

std::atomic<std::uint64_t> orient3d_fallbacks{0};
std::atomic<std::uint64_t> orient2d_fallbacks{0};

/// RAII wrapper for a GMP integer (mpz_class would need libgmpxx; the C API is enough here).
class BigInt {
 public:
  BigInt() { mpz_init(value_); }
  ~BigInt() { mpz_clear(value_); }
  BigInt(const BigInt&) = delete;
  BigInt& operator=(const BigInt&) = delete;
  mpz_ptr get() { return value_; }
  mpz_srcptr get() const { return value_; }

 private:
  mpz_t value_;
};

/// Converts finite doubles to integers that share one scale 2^min_exponent: every double is
/// m * 2^e with an integer m of at most 53 bits, so x / 2^min_exponent is an integer and the
/// determinants (homogeneous polynomials) keep their signs.
template <std::size_t N>
void to_common_scale(const std::array<double, N>& values, std::array<BigInt, N>& out) {
  int min_exponent = 0;
  bool any = false;
  for (const double v : values) {
    assert(std::isfinite(v));
    if (v != 0.0) {
      int exponent = 0;
      std::frexp(v, &exponent);  // v = f * 2^exponent, 0.5 <= |f| < 1
      min_exponent = any ? std::min(min_exponent, exponent - 53) : exponent - 53;
      any = true;
    }
  }
  for (std::size_t i = 0; i < N; ++i) {
    const double v = values[i];
    if (v == 0.0) {
      mpz_set_ui(out[i].get(), 0);
      continue;
    }
    int exponent = 0;
    const double fraction = std::frexp(v, &exponent);
    // fraction * 2^53 is an integer of at most 53 bits: exact in int64.
    const auto mantissa = static_cast<std::int64_t>(std::ldexp(fraction, 53));
    mpz_set_si(out[i].get(), static_cast<long>(mantissa));
    mpz_mul_2exp(out[i].get(), out[i].get(),
                 static_cast<mp_bitcnt_t>(exponent - 53 - min_exponent));
  }
}

}  // namespace

namespace detail {
void count_orient3d_fallback() {
  orient3d_fallbacks.fetch_add(1, std::memory_order_relaxed);
}
void count_orient2d_fallback() {
  orient2d_fallbacks.fetch_add(1, std::memory_order_relaxed);
}
}  // namespace detail

int orient3d_exact(const Eigen::Vector3d& a,
                   const Eigen::Vector3d& b,
                   const Eigen::Vector3d& c,
                   const Eigen::Vector3d& d) {
  const std::array<double, 12> values = {a.x(), a.y(), a.z(), b.x(), b.y(), b.z(),
                                         c.x(), c.y(), c.z(), d.x(), d.y(), d.z()};
  std::array<BigInt, 12> v;
  to_common_scale(values, v);
  // u = b - a, w = c - a, t = d - a (in place over b, c, d).
  for (int k = 0; k < 3; ++k) {
    for (int row = 1; row < 4; ++row) {
      mpz_sub(v[3 * row + k].get(), v[3 * row + k].get(), v[k].get());
    }
  }
  auto u = [&](int k) { return v[3 + k].get(); };
  auto w = [&](int k) { return v[6 + k].get(); };
  auto t = [&](int k) { return v[9 + k].get(); };
  BigInt det;
  BigInt minor;
  BigInt product;
  for (int k = 0; k < 3; ++k) {
    const int k1 = (k + 1) % 3;
    const int k2 = (k + 2) % 3;
    // (u x w)_k = u_k1 w_k2 - u_k2 w_k1
    mpz_mul(minor.get(), u(k1), w(k2));
    mpz_mul(product.get(), u(k2), w(k1));
    mpz_sub(minor.get(), minor.get(), product.get());
    mpz_mul(product.get(), minor.get(), t(k));
    mpz_add(det.get(), det.get(), product.get());
  }
  return mpz_sgn(det.get());
}

int orient2d_exact(double ax, double ay, double bx, double by, double cx, double cy) {
  const std::array<double, 6> values = {ax, ay, bx, by, cx, cy};
  std::array<BigInt, 6> v;
  to_common_scale(values, v);
  for (int row = 1; row < 3; ++row) {
    for (int k = 0; k < 2; ++k) {
      mpz_sub(v[2 * row + k].get(), v[2 * row + k].get(), v[k].get());
    }
  }
  BigInt left;
  BigInt right;
  mpz_mul(left.get(), v[2].get(), v[5].get());   // (bx - ax)(cy - ay)
  mpz_mul(right.get(), v[3].get(), v[4].get());  // (by - ay)(cx - ax)
  return mpz_cmp(left.get(), right.get()) > 0 ? 1 : (mpz_cmp(left.get(), right.get()) < 0 ? -1 : 0);
}

PredicateStats predicate_stats() {
  return {orient3d_fallbacks.load(std::memory_order_relaxed),
          orient2d_fallbacks.load(std::memory_order_relaxed)};
}

void reset_predicate_stats() {
  orient3d_fallbacks.store(0, std::memory_order_relaxed);
  orient2d_fallbacks.store(0, std::memory_order_relaxed);
}

}  // namespace softbench::collision
