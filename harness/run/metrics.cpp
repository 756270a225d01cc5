// SPDX-License-Identifier: MIT
#include "harness/run/metrics.h"

#include "geometry/mesh_measures.h"

#include <algorithm>
#include <cmath>

namespace softbench::harness {

Percentiles percentiles(std::vector<double> sample) {
  if (sample.empty()) {
    return {};
  }
  std::sort(sample.begin(), sample.end());
  const auto rank = [&](double fraction) {
    const auto index = static_cast<std::size_t>(std::ceil(fraction * sample.size())) - 1;
    return sample[std::min(index, sample.size() - 1)];
  };
  return {rank(0.5), rank(0.95), sample.back()};
}

double rms_distance(const Eigen::Matrix3Xd& a, const Eigen::Matrix3Xd& b) {
  if (a.cols() == 0) {
    return 0.0;
  }
  return std::sqrt((a - b).colwise().squaredNorm().mean());
}

double max_speed(const Eigen::Matrix3Xd& velocities) {
  return velocities.cols() == 0 ? 0.0 : velocities.colwise().norm().maxCoeff();
}

double kinetic_energy(const Eigen::VectorXd& masses, const Eigen::Matrix3Xd& velocities) {
  return 0.5 * masses.dot(velocities.colwise().squaredNorm().transpose());
}

void RecoveryTracker::observe(double time,
                              const Eigen::Matrix3Xd& positions,
                              const Eigen::Matrix3Xd& reference) {
  if (time < release_) {
    return;
  }
  observed_ = true;
  residual_ = rms_distance(positions, reference) / diagonal_;
  if (residual_ < kRecoveredResidual) {
    if (!below_since_) {
      below_since_ = time - release_;
    }
  } else {
    below_since_.reset();
  }
}

std::optional<double> RecoveryTracker::time_to_one_percent() const {
  return below_since_;
}

}  // namespace softbench::harness
