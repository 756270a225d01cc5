// SPDX-License-Identifier: MIT
#pragma once

#include "geometry/tet_mesh.h"
#include "harness/run/loading.h"
#include "harness/run/metrics.h"
#include "models/soft_body.h"
#include "scenes/scene.h"

#include <Eigen/Core>

#include <optional>
#include <span>

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

  /// Takes step `step` (from t = step dt) of the body under the scene's loading (input()), and
  /// with an instrument repeats it from its start while the contact's active set changes
  /// (Loading::refine): no hold pulls, no vertex ends inside the instrument, within the
  /// instrument's contact_passes (a step that runs out of them is judged at observe(): see
  /// unsettled_contact_steps()). `model_seconds` (if given) gets the time spent in the body's
  /// step() over all passes, read on `clock` (seconds; the steady clock when null): a caller
  /// that times the whole step on another clock (a thread's CPU time) passes that one, so the
  /// difference is the step's work outside the model. The step's constraints are then
  /// constraints().
  StepStats step(int step,
                 SoftBody& body,
                 double* model_seconds = nullptr,
                 double (*clock)() = nullptr);
  /// The constraints the last step() ended with.
  std::span<const PositionConstraint> constraints() const { return constraints_; }

  /// The input for step `step` (from t = step dt) from the body at the step's start; captures
  /// the recovery's reference shape when the step starts at the scene's reference time.
  StepInput input(int step, const SoftBody& body);
  /// After step `step`: the tool's force and contact measures, and the recovery residual.
  void observe(int step, const SoftBody& body);

  /// Steps observed so far that ran out of contact passes with their holds still changing (the
  /// step kept its last pass; the contact's correction would have changed it again).
  int unsettled_contact_steps() const { return unsettled_contact_steps_; }

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
  Eigen::Matrix3Xd start_positions_;  ///< the body at the step's start (contact passes)
  Eigen::Matrix3Xd start_velocities_;
  std::span<const PositionConstraint> constraints_;
  /// The last step() used every contact pass without the holds settling on one; observe()
  /// then asks whether they had settled on the last.
  bool ran_out_of_passes_ = false;
  int unsettled_contact_steps_ = 0;
};

}  // namespace softbench::harness
