// SPDX-License-Identifier: MIT
#pragma once

#include "geometry/tet_mesh.h"
#include "harness/run/loading.h"
#include "harness/run/metrics.h"
#include "models/soft_body.h"
#include "scenes/scene.h"

#include <Eigen/Core>

#include <optional>

namespace softbench::harness {

/// A body driven through a scene step by step, as `run` (the runner) and the stability
/// command's scene case both drive it: the initial velocity, gravity until the scene switches it
/// off, the fixed region, grasp and instrument (Loading), the shape recovery is measured against
/// (the body at scene.reference_time(), else the rest shape), and after each step the tool's
/// measures and the recovery. The caller calls start(), then steps the body and judges
/// divergence in between.
class SceneStepper {
 public:
  SceneStepper(const scenes::Scene& scene, const SceneMesh& mesh);

  /// Before the first step, on the fresh body: gives it the scene's initial velocity
  /// (scenes::initial_velocities). A scene without one leaves the body untouched, so its runs
  /// are bit for bit what they were.
  void start(SoftBody& body) const;

  /// The input for step `step` (from t = step dt) from the body at the step's start; captures
  /// the recovery's reference shape when the step starts at the scene's reference time.
  StepInput input(int step, const SoftBody& body);
  /// After step `step`: the tool's force and contact measures, and the recovery residual.
  void observe(int step, const SoftBody& body);

  /// Whether recovery is being measured: the reference shape has been taken.
  bool have_reference() const { return have_reference_; }
  const Loading& loading() const { return loading_; }
  const RecoveryTracker& recovery() const { return recovery_; }

 private:
  const scenes::Scene& scene_;
  std::optional<Eigen::Matrix3Xd> initial_velocities_;  ///< 3 x #V, m/s; none: start at rest
  Loading loading_;
  /// The tool force needs the constraint forces of every step; a scene without a tool does not.
  bool has_tool_ = false;
  Eigen::Matrix3Xd forces_;  ///< the last step's constraint forces (zero before the first)
  RecoveryTracker recovery_;
  Eigen::Matrix3Xd reference_;
  bool have_reference_ = false;
};

}  // namespace softbench::harness
