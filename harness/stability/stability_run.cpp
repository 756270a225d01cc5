// SPDX-License-Identifier: MIT
#include "harness/stability/stability_run.h"

#include "harness/format.h"
#include "geometry/mesh_measures.h"
#include "harness/run/metrics.h"
#include "harness/run/run_monitor.h"
#include "harness/run/scene_stepper.h"

#include <chrono>
#include <cmath>
#include <sstream>
#include <vector>

namespace softbench::harness {
namespace {

using Clock = std::chrono::steady_clock;

// Watches one run step by step and writes its verdict: RunMonitor judges divergence; this adds
// the settling, the inverted-tet counts and the wall-clock budget of the stability command.
class Monitor {
 public:
  Monitor(const TetMesh& mesh, const RunBounds& bounds, int steps_planned)
      : mesh_(mesh),
        bounds_(bounds),
        judge_(mesh, bounds.limits, bounding_box_diagonal(mesh.rest_positions())),
        start_(Clock::now()) {
    verdict_.steps_planned = steps_planned;
  }

  double diagonal() const { return judge_.diagonal(); }

  /// True once the free vertices have been slow for RunBounds::settle_steps steps in a row;
  /// records `after_release` (s) as when.
  bool settled(double after_release) {
    if (bounds_.settle_speed <= 0.0 || calm_steps_ < bounds_.settle_steps) {
      return false;
    }
    verdict_.settled_after = after_release;
    return true;
  }

  /// After step `step`; false when the run must stop. A `prescribed` step (every vertex placed
  /// by the harness) is left out of the inverted count.
  bool after_step(int step,
                  const StepStats& stats,
                  const SoftBody& body,
                  std::span<const PositionConstraint> held,
                  bool prescribed) {
    verdict_.steps_run = step + 1;
    if (!judge_.after_step(step, stats, body, held)) {
      const Divergence& divergence = *judge_.divergence();
      verdict_.status = RunStatus::kUnstable;
      verdict_.nan = divergence.non_finite;
      verdict_.diverged_at_step = divergence.step;
      verdict_.failure = divergence.reason;
      return false;
    }
    calm_steps_ = judge_.free_speed() < bounds_.settle_speed * diagonal() ? calm_steps_ + 1 : 0;
    verdict_.final_inverted_tets = count_inverted_tets(mesh_, body.positions());
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
      verdict_.time_to_one_percent = tracker->time_to_one_percent();
    }
    return verdict_;
  }

 private:
  const TetMesh& mesh_;
  RunBounds bounds_;
  RunMonitor judge_;
  Clock::time_point start_;
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

bool RunVerdict::recovered() const {
  return stable() && std::isfinite(residual) && residual < kRecoveredResidual;
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
                             const SceneMesh& mesh,
                             int steps,
                             const RunBounds& bounds) {
  Monitor monitor(mesh.body, bounds, steps);
  SceneStepper stepper(scene, mesh);
  stepper.start(body);
  for (int step = 0; step < steps; ++step) {
    const double start = step * scene.dt;
    const StepStats stats = stepper.step(step, body);
    if (!monitor.after_step(step, stats, body, stepper.constraints(), false)) {
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
