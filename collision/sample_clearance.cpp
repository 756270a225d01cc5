// SPDX-License-Identifier: MIT
#include "collision/sample_clearance.h"

#include <algorithm>
#include <cmath>

namespace softbench::collision {

SampleClearance::SampleClearance(Eigen::Index samples, const Eigen::Matrix3Xd& instrument)
    : instrument_(instrument),
      clearance_(static_cast<std::size_t>(samples), 0.0),
      travel_at_(static_cast<std::size_t>(samples), 0.0),
      side_(static_cast<std::size_t>(samples), 0) {}

void SampleClearance::advance(const Eigen::Matrix3Xd& surface, const Eigen::Isometry3d& pose) {
  if (!have_state_ || surface.cols() != surface_.cols()) {
    // No state to measure the moves from: nothing recorded so far can be trusted.
    std::fill(side_.begin(), side_.end(), static_cast<signed char>(0));
    surface_ = surface;
    pose_ = pose;
    have_state_ = true;
    return;
  }
  double surface_move = 0.0;
  for (Eigen::Index v = 0; v < surface.cols(); ++v) {
    surface_move = std::max(surface_move, (surface.col(v) - surface_.col(v)).squaredNorm());
  }
  double tool_move = 0.0;
  for (Eigen::Index v = 0; v < instrument_.cols(); ++v) {
    const Eigen::Vector3d local = instrument_.col(v);
    tool_move = std::max(tool_move, (pose * local - pose_ * local).squaredNorm());
  }
  // Rounded up by a part in a million: round-off cannot make the bound optimistic.
  constexpr double kSlack = 1.000001;
  travel_ += kSlack * (std::sqrt(surface_move) + std::sqrt(tool_move));
  surface_ = surface;
  pose_ = pose;
}

void SampleClearance::record(Eigen::Index i, double signed_distance) {
  const auto k = static_cast<std::size_t>(i);
  clearance_[k] = std::abs(signed_distance);
  travel_at_[k] = travel_;
  side_[k] = signed_distance > 0.0 ? 1 : (signed_distance < 0.0 ? -1 : 0);
}

}  // namespace softbench::collision
