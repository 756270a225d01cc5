// SPDX-License-Identifier: MIT
#pragma once

#include <Eigen/Core>
#include <nlohmann/json.hpp>

#include <cstddef>
#include <limits>
#include <span>
#include <string_view>

namespace softbench {

/// Stiffness value meaning "enforce exactly".
inline constexpr double kExact = std::numeric_limits<double>::infinity();

/// A vertex held at a target position for one step: pins, grasps and contacts all arrive this way.
/// `held` says along which directions: all three (the identity), or only some, the vertex being
/// free along the others. Held along a normal n only (n n^T, along()), it ends on the plane
/// through `target` normal to n and slides freely in it, and the constraint's force is along n
/// (a frictionless contact, a support, a symmetry plane); held across a line (I - a a^T) it
/// slides along the line through `target` in direction a (two planes at once).
struct PositionConstraint {
  int vertex = -1;
  Eigen::Vector3d target = Eigen::Vector3d::Zero();  ///< m, world frame, at the end of the step
  double stiffness = kExact;  ///< kExact: enforce exactly; finite: a penalty spring, N/m
  /// An orthogonal projector onto the held directions (symmetric, idempotent, rank 1 to 3).
  Eigen::Matrix3d held = Eigen::Matrix3d::Identity();
  /// Whether the hold anchors the body (the fixed region, a grasp: held where the scene puts it,
  /// step after step) or only keeps it out of the way this step (the instrument's contact, which
  /// comes and goes and whose corners are held only so a triangle stays under a tool's point).
  /// A model that fits clusters treats an anchoring full hold as an infinite mass in the fit;
  /// a contact hold takes part with its own mass, or a few held corners near a probe's tip would
  /// set the rotation of a whole cluster. Models that solve for positions need not care.
  bool anchors = true;

  /// The projector of a constraint held along `normal` (any length but zero) only.
  static Eigen::Matrix3d along(const Eigen::Vector3d& normal) {
    const Eigen::Vector3d n = normal.normalized();
    return n * n.transpose();
  }
  bool slides() const { return held != Eigen::Matrix3d::Identity(); }
  /// The part of the way from `x` to the target that the constraint holds: held (target - x).
  Eigen::Vector3d gap(const Eigen::Vector3d& x) const { return held * (target - x); }
  /// Where the constraint puts a vertex that would be at `x`: the target, or x moved onto the
  /// plane (line) through it. A full hold gives the target itself, not x + (target - x), which
  /// rounds.
  Eigen::Vector3d place(const Eigen::Vector3d& x) const {
    return slides() ? Eigen::Vector3d(x + gap(x)) : target;
  }
};

/// Whether a vertex's constraint (null: none) is enforced exactly, or as a penalty spring.
inline bool is_exact(const PositionConstraint* constraint) {
  return constraint != nullptr && constraint->stiffness == kExact;
}
inline bool is_penalty(const PositionConstraint* constraint) {
  return constraint != nullptr && constraint->stiffness != kExact;
}

/// Everything a scene imposes on a model for one step.
struct StepInput {
  Eigen::Vector3d gravity{0.0, 0.0, -9.81};           ///< m/s^2
  const Eigen::Matrix3Xd* external_forces = nullptr;  ///< N per vertex (3 x #V); null = none
  std::span<const PositionConstraint> constraints;    ///< at most one per vertex
};

/// What one step did and cost. Wall time is measured by the harness, never by the model, so every
/// model is timed the same way.
struct StepStats {
  int iterations = 0;      ///< solver or projection iterations
  double residual = 0.0;   ///< model-defined (documented in the model's header)
  int factorizations = 0;  ///< numeric Cholesky factorizations this step
  int linear_solves = 0;
  /// Solves (linear, or a Newton loop) that stopped at their iteration cap before meeting their
  /// tolerance: the step's answer is the cap's, not the tolerance's.
  int truncated_solves = 0;
  double max_constraint_error = 0.0;  ///< m; > 0 means constraints were only approximated
  bool finite = true;                 ///< false if NaN/Inf appeared; the harness stops the run
};

/// A deformable body simulated on the vertices of a TetMesh. Construction does all
/// precomputation (factories in model_registry.h); step() advances the state by dt.
class SoftBody {
 public:
  virtual ~SoftBody() = default;
  SoftBody(const SoftBody&) = delete;
  SoftBody& operator=(const SoftBody&) = delete;

  virtual std::string_view name() const = 0;      ///< registry key, e.g. "mass_spring"
  virtual nlohmann::json parameters() const = 0;  ///< effective parameters, defaults filled in
  virtual StepStats step(double dt, const StepInput& input) = 0;  ///< dt in s, > 0
  virtual void reset() = 0;  ///< rest positions, zero velocities

  virtual const Eigen::Matrix3Xd& positions() const = 0;   ///< 3 x #V, m, TetMesh vertex order
  virtual const Eigen::Matrix3Xd& velocities() const = 0;  ///< 3 x #V, m/s
  /// Replaces every vertex's velocity (3 x #V, m/s, finite; e.g. a body's initial motion) and
  /// keeps the positions; velocities() returns them until the next step. The next step starts
  /// from them as from the velocities a step left; its exact constraints still set the velocity
  /// of the vertices they hold. State derived from the velocities is updated with them;
  /// constraint_forces() still reports the last step. Throws std::invalid_argument for another
  /// shape or a NaN/Inf (check_velocities).
  virtual void set_velocities(const Eigen::Matrix3Xd& velocities) = 0;
  /// Puts the body back in a state it had (3 x #V each, finite): the harness repeats a step
  /// from its start with other constraints (the instrument contact's active set). Caches such as
  /// solver warm starts keep their values (guesses, not state); constraint_forces() still
  /// reports the last step. Throws std::invalid_argument as set_velocities() does.
  virtual void set_state(const Eigen::Matrix3Xd& positions, const Eigen::Matrix3Xd& velocities) = 0;

  /// N (3 x #V): the force each constraint of the last step exerted on its vertex; zero at
  /// unconstrained vertices. At static equilibrium they balance the external loads. Held by the
  /// model (valid until its next non-const call): the harness reads it after every pass of a
  /// contact step, where a copy a read was about a tenth of liver_pull's contact work.
  virtual const Eigen::Matrix3Xd& constraint_forces() const = 0;
  /// J; NaN for a model without an elastic energy (shape matching).
  virtual double elastic_energy() const;
  /// Bytes the model holds (matrices, factors, per-element data): a memory metric.
  virtual std::size_t memory_bytes() const;

 protected:
  SoftBody() = default;
  /// set_velocities()'s precondition: throws std::invalid_argument unless `velocities` is
  /// 3 x positions().cols() and finite.
  void check_velocities(const Eigen::Matrix3Xd& velocities) const;
  /// set_state()'s precondition, likewise for both.
  void check_state(const Eigen::Matrix3Xd& positions, const Eigen::Matrix3Xd& velocities) const;

 private:
  void check_field(const char* setter, const char* what, const Eigen::Matrix3Xd& field) const;
};

}  // namespace softbench
