// SPDX-License-Identifier: MIT
#include "harness/run/accuracy.h"

#include "harness/format.h"

#include <algorithm>
#include <cmath>
#include <limits>

namespace softbench::harness {
namespace {

// The relative errors of `x` against `reference` at one time: RMS and max.
std::pair<double, double> position_errors(const Eigen::Matrix3Xd& x,
                                          const Eigen::Matrix3Xd& reference,
                                          const Eigen::Matrix3Xd& rest) {
  const Eigen::VectorXd error = (x - reference).colwise().norm();
  const Eigen::VectorXd moved = (reference - rest).colwise().norm();
  // A reference that has not moved gives the error relative to a micrometre, not to zero.
  constexpr double kFloor = 1e-6;
  const double rms_moved = std::max(std::sqrt(moved.squaredNorm() / moved.size()), kFloor);
  const double max_moved = std::max(moved.maxCoeff(), kFloor);
  return {std::sqrt(error.squaredNorm() / error.size()) / rms_moved, error.maxCoeff() / max_moved};
}

}  // namespace

std::vector<double> comparison_times(const scenes::Scene& scene, int count) {
  std::vector<double> times;
  for (int i = 1; i <= count; ++i) {
    times.push_back(scene.duration * i / count);
  }
  return times;
}

std::vector<double> picture_times(const scenes::Scene& scene) {
  std::vector<double> times;
  double release = scene.duration;
  if (scene.instrument) {
    release = std::min(release, scene.instrument->release);
  }
  if (scene.grasp) {
    release = std::min(release, scene.grasp->release);
  }
  if (release < scene.duration) {
    times.push_back(release);
  }
  times.push_back(scene.duration);
  return times;
}

Accuracy accuracy_against(const std::vector<Snapshot>& snapshots,
                          double peak_tool_force,
                          const ReferenceRun& reference,
                          const Eigen::Matrix3Xd& rest) {
  Accuracy accuracy;
  double rms_sum = 0.0;
  double diagonal_sum = 0.0;
  const double diagonal = (rest.rowwise().maxCoeff() - rest.rowwise().minCoeff()).norm();
  for (std::size_t i = 0; i < reference.times.size(); ++i) {
    if (i >= snapshots.size()) {  // blew up before this time
      return {kInfinity, kInfinity, kInfinity, kInfinity, kInfinity};
    }
    const auto [rms, max] = position_errors(snapshots[i].positions, reference.positions[i], rest);
    rms_sum += rms;
    const Eigen::VectorXd distance = (snapshots[i].positions - reference.positions[i]).colwise().norm();
    diagonal_sum += std::sqrt(distance.squaredNorm() / std::max<Eigen::Index>(distance.size(), 1))
                    / std::max(diagonal, 1e-12);
    accuracy.max_error = std::max(accuracy.max_error, max);
    accuracy.volume_error =
        std::max(accuracy.volume_error,
                 std::abs(snapshots[i].volume - reference.volumes[i]) / reference.volumes[i]);
  }
  const double count = static_cast<double>(std::max<std::size_t>(reference.times.size(), 1));
  accuracy.rms_error = rms_sum / count;
  accuracy.diagonal_error = diagonal_sum / count;
  if (reference.peak_tool_force > 0.0) {
    accuracy.peak_force_error =
        std::abs(peak_tool_force - reference.peak_tool_force) / reference.peak_tool_force;
  }
  return accuracy;
}

}  // namespace softbench::harness
