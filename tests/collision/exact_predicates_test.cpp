// SPDX-License-Identifier: MIT
#include "collision/exact_predicates.h"

#include <Eigen/Geometry>
#include <gtest/gtest.h>

#include <cmath>
#include <random>

namespace softbench::collision {
namespace {

using Vec3 = Eigen::Vector3d;

TEST(ExactPredicates, Orient3dSignFollowsTheRightHandRule) {
  const Vec3 a(0, 0, 0), b(1, 0, 0), c(0, 1, 0);
  EXPECT_EQ(orient3d(a, b, c, Vec3(0.2, 0.2, 1.0)), 1);
  EXPECT_EQ(orient3d(a, b, c, Vec3(0.2, 0.2, -1.0)), -1);
  EXPECT_EQ(orient3d(a, b, c, Vec3(7.0, -3.0, 0.0)), 0);
  EXPECT_EQ(orient2d(0, 0, 1, 0, 0, 1), 1);
  EXPECT_EQ(orient2d(0, 0, 0, 1, 1, 0), -1);
  EXPECT_EQ(orient2d(0, 0, 1, 1, 3, 3), 0);
}

TEST(ExactPredicates, DecidesPointsWithinRoundoffOfAPlaneExactly) {
  // Points 0.1 + k ulp along a plane whose double evaluation cancels: the filter must defer to
  // the exact path, which sees the k-ulp offsets. x + y + z = 0.3 through three exact points.
  const Vec3 a(0.1, 0.1, 0.1), b(0.2, 0.05, 0.05), c(0.05, 0.2, 0.05);
  reset_predicate_stats();
  const Vec3 on = a;
  EXPECT_EQ(orient3d(a, b, c, on), 0);
  // The normal (b - a) x (c - a) has a positive x component.
  ASSERT_GT((b - a).cross(c - a).x(), 0.0);
  double up = 0.1;
  double down = 0.1;
  for (int k = 1; k <= 3; ++k) {
    up = std::nextafter(up, 1.0);
    down = std::nextafter(down, 0.0);
    EXPECT_EQ(orient3d(a, b, c, Vec3(up, 0.1, 0.1)), 1) << k;
    EXPECT_EQ(orient3d(a, b, c, Vec3(down, 0.1, 0.1)), -1) << k;
  }
  EXPECT_GT(predicate_stats().orient3d_fallbacks, 0u);
}

TEST(ExactPredicates, FilteredAndExactAgreeOnRandomAndNearDegenerateInput) {
  std::mt19937_64 engine(42);
  std::uniform_real_distribution<double> uniform(-1.0, 1.0);
  auto random = [&] { return Vec3(uniform(engine), uniform(engine), uniform(engine)); };
  for (int i = 0; i < 20000; ++i) {
    const Vec3 a = random(), b = random(), c = random();
    // Every other d lies on the plane up to rounding: the filter must not guess there.
    Vec3 d = random();
    if (i % 2 == 0) {
      const Vec3 n = (b - a).cross(c - a).normalized();
      d -= n.dot(d - a) * n;
    }
    ASSERT_EQ(orient3d(a, b, c, d), orient3d_exact(a, b, c, d)) << i;
    const double t = uniform(engine);
    const double px = a.x() + t * (b.x() - a.x());
    const double py = a.y() + t * (b.y() - a.y());
    ASSERT_EQ(orient2d(a.x(), a.y(), b.x(), b.y(), px, py),
              orient2d_exact(a.x(), a.y(), b.x(), b.y(), px, py))
        << i;
  }
}

TEST(ExactPredicates, ExactPathHandlesWidelyDifferentMagnitudes) {
  // 1e-200 offsets next to O(1) coordinates: products underflow in double.
  const Vec3 a(0, 0, 0), b(1, 0, 0), c(0, 1, 0);
  EXPECT_EQ(orient3d(a, b, c, Vec3(0.5, 0.5, 1e-200)), 1);
  EXPECT_EQ(orient3d(a, b, c, Vec3(0.5, 0.5, -1e-300)), -1);
  EXPECT_EQ(orient3d(Vec3(1e-160, 0, 0), Vec3(0, 1e-160, 0), Vec3(0, 0, 1e-160),
                     Vec3(1e-161, 1e-161, 1e-161)),
            -1);
}

}  // namespace
}  // namespace softbench::collision
