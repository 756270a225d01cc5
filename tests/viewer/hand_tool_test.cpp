// SPDX-License-Identifier: MIT
// The hand's instrument: a press starts above its point, the tip moves no faster than the
// hand's speed, down the normal, and a released press rises and parks out of the scene.
#include "viewer/hand_tool.h"

#include <gtest/gtest.h>

namespace softbench::viewer {
namespace {

const Eigen::Vector3d kParked(0.0, 0.0, 10.0);

ToolCommand press_at(const Eigen::Vector3d& point, const Eigen::Vector3d& normal, double depth) {
  ToolCommand command;
  command.pressing = true;
  command.point = point;
  command.normal = normal;
  command.depth = depth;
  command.press = 1;
  return command;
}

TEST(HandTool, APressStartsAboveItsPointWithTheShaftAlongTheNormal) {
  HandTool tool(kParked);
  EXPECT_TRUE(tool.parked());
  const Eigen::Vector3d normal = Eigen::Vector3d(1.0, 0.0, 1.0).normalized();
  const Eigen::Isometry3d& pose = tool.advance(press_at(Eigen::Vector3d::Zero(), normal, 0.0), 0.0);
  EXPECT_FALSE(tool.parked());
  EXPECT_LT((pose.translation() - HandTool::kHover * normal).norm(), 1e-12);
  // The mesh's shaft (+z) along the normal: the tip points into the surface.
  EXPECT_LT((pose.linear() * Eigen::Vector3d::UnitZ() - normal).norm(), 1e-12);
}

TEST(HandTool, TheTipMovesNoFasterThanTheHandsSpeedAndStopsAtTheAskedDepth) {
  HandTool tool(kParked);
  const Eigen::Vector3d normal = Eigen::Vector3d::UnitZ();
  const ToolCommand command = press_at(Eigen::Vector3d::Zero(), normal, 0.02);
  Eigen::Vector3d last = tool.advance(command, 0.0).translation();
  const double dt = 1.0 / 60.0;
  for (int step = 0; step < 60; ++step) {
    const Eigen::Vector3d now = tool.advance(command, dt).translation();
    EXPECT_LE((now - last).norm(), HandTool::kSpeed * dt * (1.0 + 1e-12));
    last = now;
  }
  // 3 cm to go at 8 cm/s: there well within the second.
  EXPECT_LT((last - Eigen::Vector3d(0.0, 0.0, -0.02)).norm(), 1e-12);
}

TEST(HandTool, AsksPastTheLimitStopAtTheLimit) {
  HandTool tool(kParked);
  const ToolCommand command = press_at(Eigen::Vector3d::Zero(), Eigen::Vector3d::UnitZ(), 1.0);
  for (int step = 0; step < 200; ++step) {
    tool.advance(command, 1.0 / 60.0);
  }
  EXPECT_NEAR(tool.pose().translation().z(), -HandTool::kMaxDepth, 1e-12);
}

TEST(HandTool, AReleasedPressRisesThenParksOutOfTheScene) {
  HandTool tool(kParked);
  ToolCommand command = press_at(Eigen::Vector3d::Zero(), Eigen::Vector3d::UnitZ(), 0.01);
  for (int step = 0; step < 30; ++step) {
    tool.advance(command, 1.0 / 60.0);
  }
  command.pressing = false;
  tool.advance(command, 1.0 / 60.0);
  EXPECT_FALSE(tool.parked());  // still rising: 2 cm to go
  for (int step = 0; step < 30; ++step) {
    tool.advance(command, 1.0 / 60.0);
  }
  EXPECT_TRUE(tool.parked());
  EXPECT_EQ(tool.pose().translation(), kParked);
  // The next press starts above its own point.
  command = press_at(Eigen::Vector3d(0.1, 0.0, 0.0), Eigen::Vector3d::UnitZ(), 0.0);
  command.press = 2;
  EXPECT_LT((tool.advance(command, 0.0).translation()
             - Eigen::Vector3d(0.1, 0.0, HandTool::kHover)).norm(),
            1e-12);
}

}  // namespace
}  // namespace softbench::viewer
