// SPDX-License-Identifier: MIT
#include "harness/run/run_monitor.h"

#include "harness/interrupt.h"

#include <cmath>
#include <sstream>

namespace softbench::harness {

RunMonitor::RunMonitor(const TetMesh& mesh, const scenes::StabilityLimits& limits, double diagonal)
    : mesh_(mesh),
      limits_(limits),
      diagonal_(diagonal),
      held_(static_cast<std::size_t>(mesh.num_vertices()), 0) {
}

bool RunMonitor::after_step(int step,
                            const StepStats& stats,
                            const SoftBody& body,
                            std::span<const PositionConstraint> held) {
  const bool within_limits = judge(step, stats, body, held);
  check_interrupted();
  return within_limits;
}

bool RunMonitor::judge(int step,
                       const StepStats& stats,
                       const SoftBody& body,
                       std::span<const PositionConstraint> held) {
  if (divergence_) {
    return false;
  }
  const Eigen::Matrix3Xd& x = body.positions();
  const Eigen::Matrix3Xd& v = body.velocities();
  if (!stats.finite || !x.allFinite() || !v.allFinite()) {
    free_speed_ = INFINITY;
    return fail(step, "NaN or Inf in the state", true);
  }
  for (const PositionConstraint& constraint : held) {
    held_[static_cast<std::size_t>(constraint.vertex)] = 1;
  }
  double speed_squared = 0.0;
  for (Eigen::Index i = 0; i < v.cols(); ++i) {
    if (held_[static_cast<std::size_t>(i)] == 0) {
      speed_squared = std::max(speed_squared, v.col(i).squaredNorm());
    }
  }
  for (const PositionConstraint& constraint : held) {
    held_[static_cast<std::size_t>(constraint.vertex)] = 0;
  }
  free_speed_ = std::sqrt(speed_squared);
  if (free_speed_ > limits_.max_speed) {
    std::ostringstream why;
    why << "speed " << free_speed_ << " m/s over the limit " << limits_.max_speed << " m/s";
    return fail(step, why.str(), false);
  }
  const double displacement = (x - mesh_.rest_positions()).colwise().norm().maxCoeff();
  if (displacement > limits_.max_displacement * diagonal_) {
    std::ostringstream why;
    why << "displacement " << displacement / diagonal_ << " bbox diagonals over the limit "
        << limits_.max_displacement;
    return fail(step, why.str(), false);
  }
  return true;
}

bool RunMonitor::fail(int step, std::string reason, bool non_finite) {
  divergence_ = Divergence{step, std::move(reason), non_finite};
  return false;
}

}  // namespace softbench::harness
