// SPDX-License-Identifier: MIT
#include "viewer/hand_tool.h"

#include <algorithm>

namespace softbench::viewer {

HandTool::HandTool(const Eigen::Vector3d& parked) : parked_position_(parked) {
  pose_.translation() = parked_position_;
}

const Eigen::Isometry3d& HandTool::advance(const ToolCommand& command, double dt) {
  if (command.pressing && (parked_ || command.press != press_)) {
    // A new press: the tool appears above its point, the shaft along the normal.
    press_ = command.press;
    point_ = command.point;
    normal_ = command.normal.normalized();
    pose_.linear() =
        Eigen::Quaterniond::FromTwoVectors(Eigen::Vector3d::UnitZ(), normal_).toRotationMatrix();
    pose_.translation() = point_ + kHover * normal_;
    parked_ = false;
  }
  if (parked_) {
    return pose_;
  }
  const double depth = std::clamp(command.depth, -kMaxDepth, kMaxDepth);
  const Eigen::Vector3d target =
      command.pressing ? Eigen::Vector3d(point_ - depth * normal_) : Eigen::Vector3d(point_ + kHover * normal_);
  const Eigen::Vector3d way = target - pose_.translation();
  const double reach = kSpeed * dt;
  pose_.translation() += way.norm() <= reach ? way : Eigen::Vector3d(reach * way.normalized());
  if (!command.pressing && way.norm() <= reach) {
    parked_ = true;  // back above the surface: out of the scene until the next press
    pose_.translation() = parked_position_;
  }
  return pose_;
}

}  // namespace softbench::viewer
