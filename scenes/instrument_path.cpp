// SPDX-License-Identifier: MIT
#include "scenes/instrument_path.h"

#include <algorithm>

namespace softbench::scenes {

Eigen::Isometry3d instrument_pose(const Instrument& instrument, double time) {
  const std::vector<InstrumentKeyframe>& path = instrument.path;
  const auto pose_of = [](const Eigen::Vector3d& position, const Eigen::Quaterniond& orientation) {
    Eigen::Isometry3d pose = Eigen::Isometry3d::Identity();
    pose.linear() = orientation.toRotationMatrix();
    pose.translation() = position;
    return pose;
  };
  if (time <= path.front().time) {
    return pose_of(path.front().position, path.front().orientation);
  }
  if (time >= path.back().time) {
    return pose_of(path.back().position, path.back().orientation);
  }
  const auto next =
      std::upper_bound(path.begin(), path.end(), time,
                       [](double t, const InstrumentKeyframe& frame) { return t < frame.time; });
  const InstrumentKeyframe& from = *(next - 1);
  const InstrumentKeyframe& to = *next;
  const double s = (time - from.time) / (to.time - from.time);
  return pose_of((1.0 - s) * from.position + s * to.position,
                 from.orientation.slerp(s, to.orientation));
}

}  // namespace softbench::scenes
