// SPDX-License-Identifier: MIT
#pragma once

#include <Eigen/Core>

namespace softbench {

/// Whether every coefficient is finite: each times zero, summed (an infinity or a NaN makes the
/// sum NaN; finite values give exactly 0), which vectorises. Eigen's allFinite() tests
/// coefficient by coefficient with a branch each: 3 us of shape matching's 65 us liver step.
inline bool all_finite(const Eigen::Matrix3Xd& values) {
  return (values.array() * 0.0).sum() == 0.0;
}

/// A step's blow-up test: its positions and velocities all finite.
inline bool state_finite(const Eigen::Matrix3Xd& positions, const Eigen::Matrix3Xd& velocities) {
  return all_finite(positions) && all_finite(velocities);
}

}  // namespace softbench
