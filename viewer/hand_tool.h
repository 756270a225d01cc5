// SPDX-License-Identifier: MIT
#pragma once

#include <Eigen/Core>
#include <Eigen/Geometry>

namespace softbench::viewer {

/// What the user's hand asks of the instrument: press at a picked surface point, some depth
/// past it along the surface's normal there, and whether to grasp the tissue under the tip.
struct ToolCommand {
  bool pressing = false;
  Eigen::Vector3d point = Eigen::Vector3d::Zero();     ///< m, the picked point, world
  Eigen::Vector3d normal = Eigen::Vector3d::UnitZ();   ///< the surface's outward normal there
  Eigen::Vector3d rest_point = Eigen::Vector3d::Zero();  ///< the picked point on the rest shape
  double depth = 0.0;  ///< m past the picked point along -normal (negative: pulled out)
  bool grasp = false;
  int press = 0;  ///< counts presses: a new value is a new point, the tool starts above it
};

/// The instrument held by a hand: the tip goes to where the command asks (the shaft along the
/// surface's normal, the tip into the surface), never faster than kSpeed, so a jump of the
/// mouse is a fast stroke and not a teleport through the tissue. A new press starts kHover above
/// its point; a released press rises back there, and the tool is then parked out of the scene
/// (far above the body, where it touches nothing and is not drawn).
class HandTool {
 public:
  static constexpr double kSpeed = 0.08;   ///< m/s, a quick surgeon's stroke
  static constexpr double kHover = 0.01;   ///< m above the surface a press starts and ends
  static constexpr double kMaxDepth = 0.05;  ///< m, either way

  /// `parked`: where the tool waits between presses (the tip's position).
  explicit HandTool(const Eigen::Vector3d& parked);

  /// Moves the tool for `dt` seconds towards what `command` asks; returns its new pose (the
  /// instrument mesh's frame -> world; the mesh has its tip at its origin and its shaft
  /// along +z).
  const Eigen::Isometry3d& advance(const ToolCommand& command, double dt);
  const Eigen::Isometry3d& pose() const { return pose_; }
  bool parked() const { return parked_; }

 private:
  Eigen::Vector3d parked_position_;
  Eigen::Isometry3d pose_ = Eigen::Isometry3d::Identity();
  bool parked_ = true;
  int press_ = 0;
  Eigen::Vector3d point_ = Eigen::Vector3d::Zero();
  Eigen::Vector3d normal_ = Eigen::Vector3d::UnitZ();
};

}  // namespace softbench::viewer
