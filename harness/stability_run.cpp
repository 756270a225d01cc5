// SPDX-License-Identifier: MIT
#include "harness/stability_run.h"

#include "geometry/mesh_measures.h"
#include "harness/metrics.h"
#include "harness/scene_stepper.h"

#include <chrono>
#include <cmath>
#include <sstream>
#include <vector>

namespace softbench::harness {
namespace {

using Clock = std::chrono::steady_clock;

double seconds_since(Clock::time_point start) {
  return std::chrono::duration<double>(Clock::now() - start).count();
}

// Watches one run step by step and writes its verdict.
class Monitor {
 public:
  Monitor(const TetMesh& mesh, const RunBounds& bounds, int steps_planned)
      : mesh_(mesh),
        bounds_(bounds),
        held_(static_cast<std::size_t>(mesh.num_vertices()), 0),
        start_(Clock::now()) {
    const Eigen::Matrix<double, 3, 2> box = bounding_box(mesh.rest_positions());
    diagonal_ = (box.col(1) - box.col(0)).norm();
    verdict_.steps_planned = steps_planned;
  }

  double diagonal() const { return diagonal_; }

  /// True once the free vertices have been slow for RunBounds::settle_steps steps in a row;
  /// records `after_release` (s) as when.
  bool settled(double after_release) {
    if (bounds_.settle_speed <= 0.0 || calm_steps_ < bounds_.settle_steps) {
      return false;
    }
    verdict_.settled_after = after_release;
    return true;
  }

  /// After step `step`; false when the run must stop. Held vertices (those constrained in the
  /// step) are left out of the speed check: their motion is prescribed, not the model's. A
  /// `prescribed` step (every vertex placed by the harness) is left out of the inverted count.
  bool after_step(int step,
                  const StepStats& stats,
                  const SoftBody& body,
                  std::span<const PositionConstraint> held,
                  bool prescribed) {
    verdict_.steps_run = step + 1;
    const Eigen::Matrix3Xd& x = body.positions();
    const Eigen::Matrix3Xd& v = body.velocities();
    if (!stats.finite || !x.allFinite() || !v.allFinite()) {
      verdict_.nan = true;
      return fail(step, "NaN or Inf in the state");
    }
    for (const PositionConstraint& constraint : held) {
      held_[static_cast<std::size_t>(constraint.vertex)] = 1;
    }
    double speed = 0.0;
    for (Eigen::Index i = 0; i < v.cols(); ++i) {
      if (held_[static_cast<std::size_t>(i)] == 0) {
        speed = std::max(speed, v.col(i).norm());
      }
    }
    for (const PositionConstraint& constraint : held) {
      held_[static_cast<std::size_t>(constraint.vertex)] = 0;
    }
    const double settle_speed = bounds_.settle_speed * diagonal_;
    calm_steps_ = speed < settle_speed ? calm_steps_ + 1 : 0;
    if (speed > bounds_.limits.max_speed) {
      std::ostringstream why;
      why << "speed " << speed << " m/s over the limit " << bounds_.limits.max_speed << " m/s";
      return fail(step, why.str());
    }
    const double displacement = (x - mesh_.rest_positions()).colwise().norm().maxCoeff();
    if (displacement > bounds_.limits.max_displacement * diagonal_) {
      std::ostringstream why;
      why << "displacement " << displacement / diagonal_ << " bbox diagonals over the limit "
          << bounds_.limits.max_displacement;
      return fail(step, why.str());
    }
    verdict_.final_inverted_tets = count_inverted_tets(mesh_, x);
    if (!prescribed) {
      verdict_.max_inverted_tets =
          std::max(verdict_.max_inverted_tets, verdict_.final_inverted_tets);
    }
    if (step + 1 < verdict_.steps_planned && seconds_since(start_) > bounds_.max_wall_seconds) {
      verdict_.status = RunStatus::kTimedOut;
      std::ostringstream why;
      why << "wall-clock budget of " << bounds_.max_wall_seconds << " s spent after " << step + 1
          << " of " << verdict_.steps_planned << " steps";
      verdict_.failure = why.str();
      return false;
    }
    return true;
  }

  /// The verdict, with the recovery of `tracker` when the run ran to its end.
  RunVerdict finish(const RecoveryTracker* tracker) {
    verdict_.wall_seconds = seconds_since(start_);
    if (verdict_.stable() && tracker != nullptr && tracker->released()) {
      verdict_.residual = tracker->residual();
      verdict_.time_to_1pct = tracker->time_to_one_percent();
    }
    return verdict_;
  }

 private:
  bool fail(int step, std::string why) {
    verdict_.status = RunStatus::kUnstable;
    verdict_.failed_at_step = step;
    verdict_.failure = std::move(why);
    return false;
  }

  const TetMesh& mesh_;
  RunBounds bounds_;
  std::vector<char> held_;
  Clock::time_point start_;
  double diagonal_ = 1.0;
  int calm_steps_ = 0;
  RunVerdict verdict_;
};

std::vector<PositionConstraint> held_at(std::span<const int> vertices,
                                        const Eigen::Matrix3Xd& positions) {
  std::vector<PositionConstraint> constraints;
  constraints.reserve(vertices.size());
  for (const int vertex : vertices) {
    constraints.push_back({vertex, positions.col(vertex), kExact});
  }
  return constraints;
}

}  // namespace

std::string to_string(RunStatus status) {
  switch (status) {
    case RunStatus::kStable:
      return "stable";
    case RunStatus::kUnstable:
      return "unstable";
    case RunStatus::kTimedOut:
      return "timed_out";
  }
  return "?";
}

bool RunVerdict::recovered(double threshold) const {
  return stable() && std::isfinite(residual) && residual < threshold;
}

RunVerdict run_hanging(SoftBody& body,
                       const TetMesh& mesh,
                       std::span<const int> fixed,
                       const Eigen::Vector3d& gravity,
                       double dt,
                       int steps,
                       const RunBounds& bounds) {
  Monitor monitor(mesh, bounds, steps);
  const std::vector<PositionConstraint> pins = held_at(fixed, mesh.rest_positions());
  StepInput input;
  input.gravity = gravity;
  input.constraints = pins;
  for (int step = 0; step < steps; ++step) {
    if (!monitor.after_step(step, body.step(dt, input), body, pins, false)) {
      break;
    }
  }
  return monitor.finish(nullptr);
}

RunVerdict run_torture(SoftBody& body,
                       const TetMesh& mesh,
                       std::span<const int> fixed,
                       const Eigen::Matrix3Xd& tortured,
                       double dt,
                       int recovery_steps,
                       const RunBounds& bounds) {
  constexpr int kPrescribedSteps = 2;  // move there, then hold there (zero velocity)
  Monitor monitor(mesh, bounds, kPrescribedSteps + recovery_steps);
  std::vector<int> every(static_cast<std::size_t>(mesh.num_vertices()));
  for (int i = 0; i < mesh.num_vertices(); ++i) {
    every[static_cast<std::size_t>(i)] = i;
  }
  const std::vector<PositionConstraint> forced = held_at(every, tortured);
  const std::vector<PositionConstraint> pins = held_at(fixed, mesh.rest_positions());
  StepInput input;
  input.gravity = Eigen::Vector3d::Zero();
  const double release = kPrescribedSteps * dt;
  RecoveryTracker recovery(release, monitor.diagonal());
  for (int step = 0; step < kPrescribedSteps + recovery_steps; ++step) {
    const bool prescribed = step < kPrescribedSteps;
    input.constraints = prescribed ? std::span<const PositionConstraint>(forced)
                                   : std::span<const PositionConstraint>(pins);
    if (!monitor.after_step(step, body.step(dt, input), body, input.constraints, prescribed)) {
      break;
    }
    if (!prescribed) {
      recovery.observe((step + 1) * dt, body.positions(), mesh.rest_positions());
      if (monitor.settled((step + 1) * dt - release)) {
        break;
      }
    }
  }
  return monitor.finish(&recovery);
}

RunVerdict run_scene_loading(SoftBody& body,
                             const scenes::Scene& scene,
                             const TetMesh& mesh,
                             int steps,
                             const RunBounds& bounds) {
  Monitor monitor(mesh, bounds, steps);
  SceneStepper stepper(scene, mesh, monitor.diagonal());
  for (int step = 0; step < steps; ++step) {
    const double start = step * scene.dt;
    const StepInput input = stepper.input(step, body);
    if (!monitor.after_step(step, body.step(scene.dt, input), body, input.constraints, false)) {
      break;
    }
    stepper.observe(step, body);
    // Only a step that began after the release can show the body at rest without its load.
    if (stepper.have_reference() && start >= scene.release_time()
        && monitor.settled(start + scene.dt - scene.release_time())) {
      break;
    }
  }
  return monitor.finish(&stepper.recovery());
}

}  // namespace softbench::harness
