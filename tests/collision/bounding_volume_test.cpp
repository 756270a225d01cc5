// SPDX-License-Identifier: MIT
#include "collision/aabb.h"
#include "collision/sphere.h"
#include "collision/sphere_aabb.h"

#include <Eigen/Core>
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <random>

namespace softbench::collision {
namespace {

constexpr int kTrials = 2000;

// Points scattered around a random centre at a random scale, including far from the origin, where
// the sphere padding has to cover the round-off of large coordinates.
Eigen::Matrix3Xd random_points(std::mt19937& rng, int count) {
  std::uniform_real_distribution<double> unit(-1.0, 1.0);
  std::uniform_real_distribution<double> log_scale(-3.0, 1.0);
  const double scale = std::pow(10.0, log_scale(rng));
  const Eigen::Vector3d offset(100.0 * unit(rng), 100.0 * unit(rng), unit(rng));
  Eigen::Matrix3Xd points(3, count);
  for (int i = 0; i < count; ++i) {
    points.col(i) = offset + scale * Eigen::Vector3d(unit(rng), unit(rng), unit(rng));
  }
  return points;
}

TEST(Aabb, FitHoldsEveryPointAndTouchesEachFace) {
  std::mt19937 rng(1);
  for (int trial = 0; trial < kTrials; ++trial) {
    const Eigen::Matrix3Xd points = random_points(rng, 1 + trial % 17);
    const Aabb box = fit_aabb(points);
    for (Eigen::Index i = 0; i < points.cols(); ++i) {
      ASSERT_TRUE(box.contains(Eigen::Vector3d(points.col(i))));
    }
    // Tight: each bound is attained by some point (min/max are exact).
    EXPECT_EQ(box.min, points.rowwise().minCoeff());
    EXPECT_EQ(box.max, points.rowwise().maxCoeff());
  }
  EXPECT_TRUE(fit_aabb(Eigen::Matrix3Xd(3, 0)).empty());
}

TEST(Aabb, MergeHoldsBoth) {
  std::mt19937 rng(4);
  for (int trial = 0; trial < kTrials; ++trial) {
    const Aabb a = fit_aabb(random_points(rng, 3)), b = fit_aabb(random_points(rng, 4));
    const Aabb merged = merge(a, b);
    EXPECT_TRUE(merged.contains(a));
    EXPECT_TRUE(merged.contains(b));
    EXPECT_EQ(merged.min, a.min.cwiseMin(b.min));
  }
}

// Brute-force references on a lattice: the overlap tests are exact statements about point sets,
// so sampling cannot prove "overlap", but a dense grid of the intersection region can find a
// common point when the volumes overlap by more than the grid spacing, and the closest-point
// construction gives the exact answer for sphere-box.
double box_box_gap(const Aabb& a, const Aabb& b) {
  double gap = 0.0;
  for (int k = 0; k < 3; ++k) {
    gap = std::max({gap, a.min[k] - b.max[k], b.min[k] - a.max[k]});
  }
  return gap;
}

TEST(Overlap, BoxBoxAgreesWithTheSeparatingAxisReference) {
  std::mt19937 rng(5);
  std::uniform_real_distribution<double> unit(-1.0, 1.0);
  int overlapping = 0;
  for (int trial = 0; trial < kTrials; ++trial) {
    Aabb a, b;
    a.extend(Eigen::Vector3d(unit(rng), unit(rng), unit(rng)));
    a.extend(Eigen::Vector3d(unit(rng), unit(rng), unit(rng)));
    b.extend(Eigen::Vector3d(unit(rng), unit(rng), unit(rng)));
    b.extend(Eigen::Vector3d(unit(rng), unit(rng), unit(rng)));
    // Boxes overlap iff no axis separates them: the largest per-axis gap is <= 0.
    const bool expected = box_box_gap(a, b) <= 0.0;
    EXPECT_EQ(overlap(a, b), expected);
    EXPECT_EQ(overlap(b, a), expected);
    overlapping += expected;
  }
  EXPECT_GT(overlapping, kTrials / 10);
  EXPECT_LT(overlapping, kTrials * 9 / 10);
  // Touching faces, edges and corners overlap (closed boxes).
  Aabb unit_box, face, corner;
  unit_box.extend(Eigen::Vector3d(0, 0, 0));
  unit_box.extend(Eigen::Vector3d(1, 1, 1));
  face.extend(Eigen::Vector3d(1, 0.2, 0.2));
  face.extend(Eigen::Vector3d(2, 0.8, 0.8));
  corner.extend(Eigen::Vector3d(1, 1, 1));
  corner.extend(Eigen::Vector3d(2, 2, 2));
  EXPECT_TRUE(overlap(unit_box, face));
  EXPECT_TRUE(overlap(unit_box, corner));
  corner.min.x() = std::nextafter(1.0, 2.0);
  EXPECT_FALSE(overlap(unit_box, corner));
}

TEST(Overlap, SphereSphereAndSphereBoxAgreeWithClosestPointReferences) {
  std::mt19937 rng(6);
  std::uniform_real_distribution<double> unit(-1.0, 1.0);
  std::uniform_real_distribution<double> radius(0.05, 0.8);
  int sphere_hits = 0, box_hits = 0;
  for (int trial = 0; trial < kTrials; ++trial) {
    const Sphere a{Eigen::Vector3d(unit(rng), unit(rng), unit(rng)), radius(rng)};
    const Sphere b{Eigen::Vector3d(unit(rng), unit(rng), unit(rng)), radius(rng)};
    // Reference: the point of a closest to b's centre lies in b.
    const Eigen::Vector3d offset = b.center - a.center;
    const Eigen::Vector3d nearest_of_a =
        a.center + offset.normalized() * std::min(a.radius, offset.norm());
    const bool spheres = (nearest_of_a - b.center).norm() <= b.radius;
    EXPECT_EQ(overlap(a, b), spheres) << "trial " << trial;
    sphere_hits += spheres;

    Aabb box;
    box.extend(Eigen::Vector3d(unit(rng), unit(rng), unit(rng)));
    box.extend(Eigen::Vector3d(unit(rng), unit(rng), unit(rng)));
    const Eigen::Vector3d clamped = a.center.cwiseMax(box.min).cwiseMin(box.max);
    const bool mixed = (clamped - a.center).norm() <= a.radius;
    EXPECT_EQ(overlap(a, box), mixed) << "trial " << trial;
    EXPECT_EQ(overlap(box, a), mixed) << "trial " << trial;
    EXPECT_NEAR(std::sqrt(squared_distance(box, a.center)), (clamped - a.center).norm(), 1e-15);
    box_hits += mixed;
  }
  EXPECT_GT(sphere_hits, kTrials / 10);
  EXPECT_LT(sphere_hits, kTrials * 9 / 10);
  EXPECT_GT(box_hits, kTrials / 10);
  EXPECT_LT(box_hits, kTrials * 9 / 10);
}

// circumspheres_overlap against the formed circumspheres. The exact answer is compared only where
// the sphere gap is clear of round-off; near tangency the test may only err towards "overlap",
// which the box-overlap property checks exactly: boxes that overlap (even at one corner, far from
// the origin, with coordinates that have no short binary form) always have overlapping
// circumspheres, by the triangle inequality on their half-diagonals.
TEST(SphereAabb, CircumspheresOverlapMatchesTheFormedSpheresAndNeverRejectsOverlappingBoxes) {
  std::mt19937 rng(9);
  std::uniform_real_distribution<double> shift(-1.0, 1.0);
  int overlapping = 0, decided = 0;
  for (int trial = 0; trial < kTrials; ++trial) {
    // b: a's points moved by up to their spread per axis, so that a good share overlap.
    const Eigen::Matrix3Xd points = random_points(rng, 3);
    const Aabb a = fit_aabb(points);
    const Eigen::Vector3d move =
        a.extent().norm() * Eigen::Vector3d(shift(rng), shift(rng), shift(rng));
    const Aabb b = fit_aabb((points.colwise() + move).eval());
    const double magnitude = std::max(coordinate_magnitude(a), coordinate_magnitude(b));
    const Sphere sa = circumsphere(a), sb = circumsphere(b);
    const double gap = (sa.center - sb.center).norm() - sa.radius - sb.radius;
    const bool result = circumspheres_overlap(a, b, magnitude);
    EXPECT_EQ(result, circumspheres_overlap(b, a, magnitude)) << "trial " << trial;
    if (std::abs(gap) > 1e-9 * (sa.radius + sb.radius + magnitude)) {
      EXPECT_EQ(result, gap <= 0.0) << "trial " << trial;
      ++decided;
    }
    if (overlap(a, b)) {
      EXPECT_TRUE(result) << "trial " << trial;
    }
    overlapping += result;
  }
  EXPECT_GT(decided, kTrials * 9 / 10);
  EXPECT_GT(overlapping, kTrials / 10);
  EXPECT_LT(overlapping, kTrials * 9 / 10);

  // Boxes of one shape touching at a corner: their circumspheres touch at that corner.
  std::uniform_real_distribution<double> unit(0.1, 1.0);
  for (const double offset : {0.0, 0.3, 1e3, -7e6, 1e12}) {
    for (int trial = 0; trial < 200; ++trial) {
      const Eigen::Vector3d size(unit(rng), unit(rng), unit(rng));
      Aabb a, b;
      a.extend(Eigen::Vector3d::Constant(offset) + 0.1 * size);
      a.extend(Eigen::Vector3d::Constant(offset) + 1.1 * size);
      b.extend(a.max);
      b.extend(a.max + (a.max - a.min));
      const double magnitude = std::max(coordinate_magnitude(a), coordinate_magnitude(b));
      ASSERT_TRUE(overlap(a, b));
      EXPECT_TRUE(circumspheres_overlap(a, b, magnitude)) << "offset " << offset;
      // Moved apart along the diagonal by more than round-off, they miss.
      const Eigen::Vector3d away = (1e-6 + 1e-12 * std::abs(offset)) * size;
      Aabb apart = b;
      apart.min += away;
      apart.max += away;
      EXPECT_FALSE(circumspheres_overlap(a, apart, magnitude + 1.0))
          << "offset " << offset << " trial " << trial;
    }
  }
}

}  // namespace
}  // namespace softbench::collision
