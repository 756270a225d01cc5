// SPDX-License-Identifier: MIT
// The expansion arithmetic and the exact predicates built on it, checked against GMP rationals
// (CGAL::Gmpq, exact for every double) on random, near-coplanar and extreme-exponent input.
#include "collision/expansion_arithmetic.h"

#include "collision/exact_predicates.h"

#include <CGAL/Gmpq.h>
#include <Eigen/Geometry>
#include <gtest/gtest.h>

#include <array>
#include <cmath>
#include <random>
#include <vector>

namespace softbench::collision {
namespace {

using Vec3 = Eigen::Vector3d;

/// CGAL's GMP rational: exact for every double and every sum and product of them.
using Rational = CGAL::Gmpq;

int sign_of(const Rational& x) {
  return static_cast<int>(CGAL::sign(x));
}

Rational exact_value(std::span<const double> e) {
  Rational r;
  for (const double c : e) {
    r = r + Rational(c);
  }
  return r;
}

int gmp_orient3d(const Vec3& a, const Vec3& b, const Vec3& c, const Vec3& d) {
  auto diff = [](const Vec3& x, const Vec3& y, int k) { return Rational(x[k]) - Rational(y[k]); };
  Rational det;
  for (int k = 0; k < 3; ++k) {
    const int i = (k + 1) % 3;
    const int j = (k + 2) % 3;
    det = det + (diff(b, a, i) * diff(c, a, j) - diff(b, a, j) * diff(c, a, i)) * diff(d, a, k);
  }
  return sign_of(det);
}

int gmp_orient2d(double ax, double ay, double bx, double by, double cx, double cy) {
  const Rational left = (Rational(bx) - Rational(ax)) * (Rational(cy) - Rational(ay));
  const Rational right = (Rational(by) - Rational(ay)) * (Rational(cx) - Rational(ax));
  return sign_of(left - right);
}

/// A nonoverlapping, increasing, zero-free expansion (a single 0 for zero).
::testing::AssertionResult well_formed(std::span<const double> e) {
  if (e.size() == 1) {
    return ::testing::AssertionSuccess();
  }
  for (std::size_t i = 0; i < e.size(); ++i) {
    if (e[i] == 0.0) {
      return ::testing::AssertionFailure() << "zero component " << i;
    }
    if (i > 0 && !(std::abs(e[i - 1]) < std::abs(e[i]))) {
      return ::testing::AssertionFailure()
             << "components " << i - 1 << ", " << i << " out of order";
    }
  }
  return ::testing::AssertionSuccess();
}

/// Doubles whose exponents span [-scale, scale] binary orders (no underflow in products).
class Doubles {
 public:
  explicit Doubles(std::uint64_t seed) : engine_(seed) {}
  double operator()(int scale) {
    const double m = std::uniform_real_distribution<double>(-1.0, 1.0)(engine_);
    return std::ldexp(m, std::uniform_int_distribution<int>(-scale, scale)(engine_));
  }
  std::mt19937_64& engine() { return engine_; }

 private:
  std::mt19937_64 engine_;
};

TEST(ExpansionArithmetic, SumScaleAndProductAreExactAndWellFormed) {
  Doubles random(11);
  for (int trial = 0; trial < 2000; ++trial) {
    // e and f: sums of 1-4 doubles of widely different magnitudes, built by exact sums.
    auto build = [&](std::vector<double>& out) {
      out = {random(60)};
      const int terms = 1 + trial % 4;
      for (int t = 0; t < terms; ++t) {
        std::vector<double> next(out.size() + 1);
        const double x = random(60);
        next.resize(expansion::sum(out, std::span<const double>(&x, 1), next));
        out = next;
      }
    };
    std::vector<double> e;
    std::vector<double> f;
    build(e);
    build(f);
    ASSERT_TRUE(well_formed(e));
    std::vector<double> h(e.size() + f.size());
    h.resize(expansion::sum(e, f, h));
    ASSERT_TRUE(well_formed(h)) << trial;
    ASSERT_TRUE(exact_value(h) == exact_value(e) + exact_value(f)) << trial;

    const double b = random(60);
    std::vector<double> scaled(2 * e.size());
    scaled.resize(expansion::scale<false>(e, b, scaled));
    ASSERT_TRUE(well_formed(scaled)) << trial;
    ASSERT_TRUE(exact_value(scaled) == exact_value(e) * Rational(b)) << trial;

    std::vector<double> product(2 * e.size() * f.size());
    std::vector<double> scratch(product.size());
    product.resize(expansion::product<false>(e, f, product, scratch));
    ASSERT_TRUE(well_formed(product)) << trial;
    ASSERT_TRUE(exact_value(product) == exact_value(e) * exact_value(f)) << trial;
    ASSERT_EQ(expansion::sign(product), sign_of(exact_value(e) * exact_value(f))) << trial;
  }
}

TEST(ExpansionArithmetic, TwoProductWithFmaEqualsDekker) {
  Doubles random(12);
  for (int trial = 0; trial < 10000; ++trial) {
    const double a = random(400);
    const double b = random(400);
    double x1 = 0.0, y1 = 0.0, x2 = 0.0, y2 = 0.0;
    expansion::two_product<true>(a, b, x1, y1);
    expansion::two_product<false>(a, b, x2, y2);
    ASSERT_EQ(x1, x2);
    ASSERT_EQ(y1, y2) << a << " * " << b;
  }
}

/// Every exact orient3d path (expansions with FMA and with Dekker's product, wide integers)
/// against GMP on one input.
::testing::AssertionResult orient3d_paths_agree(const Vec3& a,
                                                const Vec3& b,
                                                const Vec3& c,
                                                const Vec3& d) {
  const int expected = gmp_orient3d(a, b, c, d);
  const std::array<int, 4> got = {orient3d_exact(a, b, c, d),
                                  detail::orient3d_exact_without_fma(a, b, c, d),
                                  detail::orient3d_exact_wide(a, b, c, d), orient3d(a, b, c, d)};
  for (const int g : got) {
    if (g != expected) {
      return ::testing::AssertionFailure()
             << "GMP " << expected << ", paths " << got[0] << got[1] << got[2] << got[3];
    }
  }
  return ::testing::AssertionSuccess();
}

TEST(ExactPredicatesAgainstGmp, Orient3dOnRandomAndNearCoplanarPoints) {
  Doubles random(21);
  std::uniform_real_distribution<double> unit(-1.0, 1.0);
  auto point = [&] {
    return Vec3(unit(random.engine()), unit(random.engine()), unit(random.engine()));
  };
  for (int trial = 0; trial < 3000; ++trial) {
    const Vec3 a = point(), b = point(), c = point();
    Vec3 d = point();
    if (trial % 3 != 0) {
      // Onto the plane in floating point: within a few ulps of it, exactly on it sometimes.
      const Vec3 n = (b - a).cross(c - a).normalized();
      d -= n.dot(d - a) * n;
    }
    ASSERT_TRUE(orient3d_paths_agree(a, b, c, d)) << trial;
    // Points on a line through a with dyadic steps: exactly coplanar quadruples.
    const Vec3 direction = point();
    ASSERT_TRUE(orient3d_paths_agree(a, a + 0.5 * direction, b, a - 0.25 * direction)) << trial;
  }
}

TEST(ExactPredicatesAgainstGmp, Orient3dWithHugeAndTinyExponents) {
  Doubles random(22);
  for (int trial = 0; trial < 2000; ++trial) {
    // Mixed exponents within one call: up to 2^+-300 (expansions after scaling), then
    // 2^+-1000 (wide integers), including subnormals.
    const int scale = trial % 2 == 0 ? 300 : 1000;
    auto point = [&] { return Vec3(random(scale), random(scale), random(scale)); };
    const Vec3 a = point(), b = point(), c = point(), d = point();
    ASSERT_TRUE(orient3d_paths_agree(a, b, c, d)) << trial;
    // A coplanar configuration scaled by 2^k (exact), offset by one ulp in z.
    const double s =
        std::ldexp(1.0, std::uniform_int_distribution<int>(-1000, 900)(random.engine()));
    const Vec3 p(s, 0, 0), q(0, s, 0), r(0, 0, s), x(s / 4, s / 4, s / 2);
    ASSERT_TRUE(orient3d_paths_agree(p, q, r, x)) << trial;
    ASSERT_TRUE(orient3d_paths_agree(p, q, r, Vec3(x.x(), x.y(), std::nextafter(x.z(), 0.0))))
        << trial;
  }
  // Subnormal and largest finite coordinates.
  const double tiny = std::numeric_limits<double>::denorm_min();
  const double big = std::numeric_limits<double>::max() / 4;
  EXPECT_TRUE(orient3d_paths_agree(Vec3(0, 0, 0), Vec3(tiny, 0, 0), Vec3(0, tiny, 0),
                                   Vec3(tiny, tiny, tiny)));
  EXPECT_TRUE(
      orient3d_paths_agree(Vec3(0, 0, 0), Vec3(big, 0, 0), Vec3(0, big, 0), Vec3(big, big, -tiny)));
  EXPECT_TRUE(orient3d_paths_agree(Vec3(1, 0, 0), Vec3(0, 1, 0), Vec3(0, 0, 1),
                                   Vec3(1.0 / 3.0, 1.0 / 3.0, 1.0 / 3.0)));
}

TEST(ExactPredicatesAgainstGmp, Orient2dOnNearCollinearAndExtremeInput) {
  Doubles random(23);
  for (int trial = 0; trial < 5000; ++trial) {
    const int scale = trial % 3 == 0 ? 1000 : 40;
    const double ax = random(scale), ay = random(scale), bx = random(scale), by = random(scale);
    const double t = std::uniform_real_distribution<double>(-2.0, 2.0)(random.engine());
    // c on the line ab in floating point (within rounding), or anywhere.
    const double cx = trial % 2 == 0 ? ax + t * (bx - ax) : random(scale);
    const double cy = trial % 2 == 0 ? ay + t * (by - ay) : random(scale);
    ASSERT_EQ(orient2d_exact(ax, ay, bx, by, cx, cy), gmp_orient2d(ax, ay, bx, by, cx, cy))
        << trial;
    ASSERT_EQ(orient2d(ax, ay, bx, by, cx, cy), gmp_orient2d(ax, ay, bx, by, cx, cy)) << trial;
  }
}

}  // namespace
}  // namespace softbench::collision
