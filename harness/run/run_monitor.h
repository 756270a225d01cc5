// SPDX-License-Identifier: MIT
#pragma once

#include "geometry/tet_mesh.h"
#include "models/soft_body.h"
#include "scenes/scene.h"

#include <optional>
#include <span>
#include <string>
#include <vector>

namespace softbench::harness {

/// Why and when a run was stopped.
struct Divergence {
  int step = -1;
  std::string reason;
  bool non_finite = false;  ///< a NaN or Inf appeared (else a limit was exceeded)
};

/// The one divergence rule, used by every command that steps a body (run, sweep, stability,
/// calibrate), so no two of them can judge the same run differently. After each step the run
/// has diverged when
/// - the step reported a non-finite result, or a position or velocity is NaN or Inf;
/// - a free vertex is faster than limits.max_speed (m/s). A vertex held by a position constraint
///   in that step (the fixed region, a grasp, instrument contact, a shape the harness prescribes)
///   moves as the harness moves it, not as the model does, so its speed is not judged;
/// - any vertex, held or free, is further from its rest position than limits.max_displacement
///   times the rest bounding-box diagonal (a held vertex so far away means the scene, not the
///   model, is broken, and a result from it means nothing either).
/// Once diverged, the verdict stays.
class RunMonitor {
 public:
  RunMonitor(const TetMesh& mesh, const scenes::StabilityLimits& limits, double diagonal);

  /// Judges the body after step `step` with the constraints it was given (`held`); false once
  /// the run has diverged. Then, the step judged, throws Interrupted if a stop was asked for:
  /// every simulation loop calls this once a step, so a stop lands between two steps.
  bool after_step(int step,
                  const StepStats& stats,
                  const SoftBody& body,
                  std::span<const PositionConstraint> held);

  const std::optional<Divergence>& divergence() const { return divergence_; }
  bool diverged() const { return divergence_.has_value(); }
  /// m/s: the largest free-vertex speed after the last step judged (the quantity the speed
  /// limit applies to).
  double free_speed() const { return free_speed_; }
  double diagonal() const { return diagonal_; }

 private:
  bool judge(int step,
             const StepStats& stats,
             const SoftBody& body,
             std::span<const PositionConstraint> held);
  bool fail(int step, std::string reason, bool non_finite);

  const TetMesh& mesh_;
  scenes::StabilityLimits limits_;
  double diagonal_;
  std::vector<char> held_;  ///< scratch: 1 for the vertices constrained in the step judged
  double free_speed_ = 0.0;
  std::optional<Divergence> divergence_;
};

}  // namespace softbench::harness
