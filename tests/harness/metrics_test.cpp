// SPDX-License-Identifier: MIT
#include "harness/run/metrics.h"

#include "geometry/mesh_validation.h"
#include "tests/test_meshes.h"
#include "tests/test_tolerances.h"

#include <gtest/gtest.h>

namespace softbench::harness {
namespace {

TEST(Percentiles, UseNearestRankOnTheSortedSample) {
  std::vector<double> sample;
  for (int i = 100; i >= 1; --i) {
    sample.push_back(i);
  }
  const Percentiles p = percentiles(sample);
  EXPECT_EQ(p.median, 50.0);
  EXPECT_EQ(p.p95, 95.0);
  EXPECT_EQ(p.max, 100.0);
  EXPECT_EQ(percentiles({}).max, 0.0);
}

TEST(CountInvertedTets, CountsTetsTurnedInsideOut) {
  const TetMesh mesh = make_tet_mesh(test::box_tets(2, 1, 1));
  EXPECT_EQ(count_inverted_tets(mesh, mesh.rest_positions()), 0);
  Eigen::Matrix3Xd mirrored = mesh.rest_positions();
  mirrored.row(2) *= -1.0;  // a reflection inverts every tet
  EXPECT_EQ(count_inverted_tets(mesh, mirrored), mesh.num_tets());
  Eigen::Matrix3Xd flat = mesh.rest_positions();
  flat.row(2).setZero();  // zero volume counts as inverted: the element has collapsed
  EXPECT_EQ(count_inverted_tets(mesh, flat), mesh.num_tets());
}

TEST(KineticEnergy, IsHalfMassTimesSpeedSquared) {
  Eigen::VectorXd masses(2);
  masses << 2.0, 4.0;
  Eigen::Matrix3Xd velocities(3, 2);
  velocities << 1, 0, 0, 2, 0, 0;
  EXPECT_NEAR(kinetic_energy(masses, velocities), 0.5 * 2 * 1 + 0.5 * 4 * 4, test::kRoundoff);
  EXPECT_NEAR(max_speed(velocities), 2.0, test::kRoundoff);
}

TEST(RecoveryTracker, MeasuresFromReleaseAndRestartsWhenTheResidualRisesAgain) {
  const Eigen::Matrix3Xd reference = Eigen::Matrix3Xd::Zero(3, 1);
  Eigen::Matrix3Xd shifted = reference;
  RecoveryTracker tracker(/*release_time=*/1.0, /*diagonal=*/1.0);
  shifted(0, 0) = 0.5;
  tracker.observe(0.5, shifted, reference);  // before release: ignored
  EXPECT_FALSE(tracker.released());
  tracker.observe(1.1, shifted, reference);
  EXPECT_NEAR(tracker.residual(), 0.5, test::kRoundoff);
  EXPECT_FALSE(tracker.time_to_one_percent());
  shifted(0, 0) = 0.005;
  tracker.observe(1.2, shifted, reference);
  ASSERT_TRUE(tracker.time_to_one_percent());
  EXPECT_NEAR(*tracker.time_to_one_percent(), 0.2, test::kRoundoff);
  shifted(0, 0) = 0.02;  // an overshoot: not recovered after all
  tracker.observe(1.3, shifted, reference);
  EXPECT_FALSE(tracker.time_to_one_percent());
  shifted(0, 0) = 0.0;
  tracker.observe(1.4, shifted, reference);
  EXPECT_NEAR(*tracker.time_to_one_percent(), 0.4, test::kRoundoff);
}

}  // namespace
}  // namespace softbench::harness
