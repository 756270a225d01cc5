// SPDX-License-Identifier: MIT
#include "scenes/instrument_path.h"

#include <gtest/gtest.h>

#include <numbers>

namespace softbench::scenes {
namespace {

Instrument two_keyframes() {
  Instrument instrument;
  InstrumentKeyframe from;
  from.time = 1.0;
  from.position = {0.0, 0.0, 1.0};
  InstrumentKeyframe to;
  to.time = 3.0;
  to.position = {2.0, 0.0, 1.0};
  to.orientation =
      Eigen::Quaterniond(Eigen::AngleAxisd(std::numbers::pi / 2, Eigen::Vector3d::UnitZ()));
  instrument.path = {from, to};
  return instrument;
}

TEST(InstrumentPath, HoldsTheFirstPoseBeforeTheFirstKeyframe) {
  const Eigen::Isometry3d pose = instrument_pose(two_keyframes(), 0.0);
  EXPECT_TRUE(pose.translation().isApprox(Eigen::Vector3d(0.0, 0.0, 1.0)));
  EXPECT_TRUE(pose.linear().isIdentity(1e-15));
}

TEST(InstrumentPath, HoldsTheLastPoseAfterTheLastKeyframe) {
  const Eigen::Isometry3d pose = instrument_pose(two_keyframes(), 10.0);
  EXPECT_TRUE(pose.translation().isApprox(Eigen::Vector3d(2.0, 0.0, 1.0)));
  EXPECT_TRUE((pose.linear() * Eigen::Vector3d::UnitX()).isApprox(Eigen::Vector3d::UnitY(), 1e-15));
}

TEST(InstrumentPath, MovesLinearlyAndTurnsAtAConstantRateBetweenKeyframes) {
  const Eigen::Isometry3d pose = instrument_pose(two_keyframes(), 1.5);  // a quarter of the way
  EXPECT_TRUE(pose.translation().isApprox(Eigen::Vector3d(0.5, 0.0, 1.0), 1e-15));
  const Eigen::AngleAxisd turned(pose.linear());
  EXPECT_NEAR(turned.angle(), std::numbers::pi / 8, 1e-12);  // slerp: a quarter of 90 degrees
  EXPECT_TRUE(turned.axis().isApprox(Eigen::Vector3d::UnitZ(), 1e-12));
}

TEST(InstrumentPath, PassesThroughEveryKeyframe) {
  Instrument instrument = two_keyframes();
  InstrumentKeyframe third;
  third.time = 4.0;
  third.position = {5.0, 5.0, 5.0};
  instrument.path.push_back(third);
  EXPECT_TRUE(instrument_pose(instrument, 3.0).translation().isApprox(Eigen::Vector3d(2, 0, 1)));
  EXPECT_TRUE(
      instrument_pose(instrument, 3.5).translation().isApprox(Eigen::Vector3d(3.5, 2.5, 3)));
}

}  // namespace
}  // namespace softbench::scenes
