// SPDX-License-Identifier: MIT
#include "collision/sample_clearance.h"

#include <algorithm>
#include <cmath>

namespace softbench::collision {

double largest_move(const Eigen::Matrix3Xd& from,
                    const Eigen::Matrix3Xd& to,
                    const Eigen::Vector3d& shift) {
  double largest = 0.0;
  for (Eigen::Index v = 0; v < from.cols(); ++v) {
    largest = std::max(largest, (to.col(v) - from.col(v) - shift).squaredNorm());
  }
  return std::sqrt(largest);
}

double largest_move(const Eigen::Matrix3Xd& vertices,
                    const Eigen::Isometry3d& from,
                    const Eigen::Isometry3d& to,
                    const Eigen::Vector3d& shift) {
  if (from.matrix() == to.matrix() && shift.isZero()) {
    return 0.0;  // the contact's passes within a step: the instrument has not moved
  }
  double largest = 0.0;
  for (Eigen::Index v = 0; v < vertices.cols(); ++v) {
    const Eigen::Vector3d local = vertices.col(v);
    largest = std::max(largest, (to * local - from * local - shift).squaredNorm());
  }
  return std::sqrt(largest);
}

SampleClearance::SampleClearance(Eigen::Index samples, const Eigen::Matrix3Xd& instrument)
    : instrument_(instrument),
      clearance_(static_cast<std::size_t>(samples), 0.0),
      travel_at_(static_cast<std::size_t>(samples), 0.0),
      side_(static_cast<std::size_t>(samples), 0),
      triangle_(static_cast<std::size_t>(samples), -1) {
}

void SampleClearance::advance(const Eigen::Matrix3Xd& surface, const Eigen::Isometry3d& pose) {
  if (!have_state_ || surface.cols() != surface_.cols()) {
    // No state to measure the moves from: nothing recorded so far can be trusted.
    std::fill(side_.begin(), side_.end(), static_cast<signed char>(0));
    std::fill(clearance_.begin(), clearance_.end(), 0.0);
    std::fill(triangle_.begin(), triangle_.end(), -1);
    surface_ = surface;
    pose_ = pose;
    have_state_ = true;
    return;
  }
  // Rounded up by a part in a million: round-off cannot make the bound optimistic.
  constexpr double kSlack = 1.000001;
  // Relative to the instrument's own shift (its frame's origin's move): a tissue that follows
  // the tool (pressed, grasped) keeps its clearance, where the sum of the two largest moves
  // spent twice the tool's motion a step.
  const Eigen::Vector3d shift = pose.translation() - pose_.translation();
  // Differences of nearly equal coordinates are rounded absolutely, not relatively: a picometre
  // a change covers that (coordinates of metres round at 1e-16 m).
  constexpr double kRoundoff = 1e-12;
  travel_ +=
      kSlack
          * (largest_move(surface_, surface, shift) + largest_move(instrument_, pose_, pose, shift))
      + kRoundoff;
  surface_ = surface;
  pose_ = pose;
}

void SampleClearance::record(Eigen::Index i, double signed_distance, int triangle) {
  const auto k = static_cast<std::size_t>(i);
  triangle_[k] = triangle;
  clearance_[k] = std::abs(signed_distance);
  travel_at_[k] = travel_;
  side_[k] = signed_distance > 0.0 ? 1 : (signed_distance < 0.0 ? -1 : 0);
}

void SampleClearance::record_far(Eigen::Index i, double distance) {
  const auto k = static_cast<std::size_t>(i);
  clearance_[k] = distance;
  travel_at_[k] = travel_;
  side_[k] = 0;
}

}  // namespace softbench::collision
