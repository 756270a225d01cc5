// SPDX-License-Identifier: MIT
#pragma once

#include "geometry/tet_mesh.h"
#include "harness/run/scene_mesh.h"
#include "models/soft_body.h"
#include "scenes/scene.h"

#include <Eigen/Core>

#include <limits>
#include <optional>
#include <span>
#include <string>

namespace softbench::harness {

// The bounded runs `softbench stability` is made of. Each stops at the first step that blows up
// (RunMonitor's rule, the same as every other command's), at its step count, or when its
// wall-clock budget is spent, so no run can hang the command.

enum class RunStatus {
  kStable,    ///< every step ran within the limits
  kUnstable,  ///< a step blew up (see RunVerdict::failure)
  kTimedOut,  ///< the wall-clock budget ran out first: neither stable nor unstable
};
/// "stable", "unstable", "timed_out".
std::string to_string(RunStatus status);

/// What one bounded run found.
struct RunVerdict {
  RunStatus status = RunStatus::kStable;
  bool nan = false;     ///< a NaN or Inf appeared in the state
  std::string failure;  ///< why it stopped early ("" when it ran to the end)
  int diverged_at_step = -1;
  int steps_planned = 0;
  int steps_run = 0;
  double wall_seconds = 0.0;
  int max_inverted_tets = 0;    ///< over the steps the model itself moved the body
  int final_inverted_tets = 0;  ///< at the last step run (> 0 at the end: stuck inverted)
  /// Recovery residual at the end: RMS distance to the shape recovered toward / the rest
  /// bounding-box diagonal. NaN when not measured (the run failed, or nothing was released).
  double residual = std::numeric_limits<double>::quiet_NaN();
  std::optional<double> time_to_one_percent;  ///< s after release; see kRecoveredResidual
  /// s after release at which the body came to rest and the run ended early (see RunBounds).
  std::optional<double> settled_after;

  bool stable() const { return status == RunStatus::kStable; }
  /// Stable, and the final residual is below kRecoveredResidual.
  bool recovered() const;
};

/// Limits and budget shared by every run of one body.
struct RunBounds {
  scenes::StabilityLimits limits;
  double max_wall_seconds = 60.0;  ///< s per run; beyond it the run reports kTimedOut
  /// A recovery ends early once every free vertex has been slower than this many bbox diagonals
  /// per second for `settle_steps` steps in a row: over a 10 s window the shape can then change
  /// by at most 0.1% of the diagonal more, a tenth of kRecoveredResidual. 0: never.
  double settle_speed = 1e-4;
  int settle_steps = 10;
};

/// `steps` steps of dt with `fixed` held at rest and gravity on: the stability map's run.
RunVerdict run_hanging(SoftBody& body,
                       const TetMesh& mesh,
                       std::span<const int> fixed,
                       const Eigen::Vector3d& gravity,
                       double dt,
                       int steps,
                       const RunBounds& bounds);

/// Forces the body into `tortured` (3 x #V) and lets it recover: one step with every vertex
/// constrained exactly to it, one more holding it there (so the body starts from rest in the
/// tortured shape: these two steps are prescribed, not the model's), then `recovery_steps` with
/// only `fixed` held, at rest, and no gravity. The residual is measured against the rest shape,
/// the equilibrium of that recovery phase. Ends early once the body has settled.
RunVerdict run_torture(SoftBody& body,
                       const TetMesh& mesh,
                       std::span<const int> fixed,
                       const Eigen::Matrix3Xd& tortured,
                       double dt,
                       int recovery_steps,
                       const RunBounds& bounds);

/// The scene's own loading (fixed region, gravity and its switch-off, grasp, instrument) on
/// `mesh` for `steps` steps of scene.dt, with recovery measured as the runner measures it
/// (against the shape at scene.reference_time(), from scene.release_time()). Ends early once
/// the body has settled after the release.
RunVerdict run_scene_loading(SoftBody& body,
                             const scenes::Scene& scene,
                             const SceneMesh& mesh,
                             int steps,
                             const RunBounds& bounds);

}  // namespace softbench::harness
