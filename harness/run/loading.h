// SPDX-License-Identifier: MIT
#pragma once

#include "collision/instrument_contact.h"
#include "geometry/tet_mesh.h"
#include "harness/run/scene_mesh.h"
#include "models/soft_body.h"
#include "scenes/scene.h"

#include <Eigen/Core>
#include <Eigen/Geometry>

#include <memory>
#include <optional>
#include <span>
#include <vector>

namespace softbench::harness {

/// Everything a scene does to the body besides gravity, one step at a time: the fixed region,
/// the grasp, and the instrument with its contact. It also measures what the tissue does to the
/// tool (the force), how far the tool has moved, and how well contact held.
class Loading {
 public:
  Loading(const scenes::Scene& scene, const SceneMesh& mesh);
  ~Loading();
  Loading(const Loading&) = delete;
  Loading& operator=(const Loading&) = delete;

  /// The constraints for the step [start, start + dt], from the body at the step's start
  /// (positions and velocities) and the constraint forces of the previous step (3 x #V, N;
  /// zero before the first step).
  std::span<const PositionConstraint> constraints(double start,
                                                  double dt,
                                                  const Eigen::Matrix3Xd& positions,
                                                  const Eigen::Matrix3Xd& velocities,
                                                  const Eigen::Matrix3Xd& last_forces);

  /// After the step was taken with constraints()'s constraints (or the last refine()'s), to
  /// `positions` with `forces` on its constraints: the instrument contact's active-set
  /// correction (collision::InstrumentContact::refine). The new constraints when it changed
  /// them (the caller repeats the step from its start with them), else none.
  std::optional<std::span<const PositionConstraint>> refine(const Eigen::Matrix3Xd& positions,
                                                            const Eigen::Matrix3Xd& forces);
  /// Whether the step's holds had settled where it ended (at `positions` with `forces`): refine()
  /// would change nothing. Changes nothing itself; true without an instrument.
  bool contact_settled(const Eigen::Matrix3Xd& positions, const Eigen::Matrix3Xd& forces);
  /// After the step ending at `end`: the tool force from the step's constraint forces, and the
  /// contact measures (penetration, vertices that lost contact) at the step's end.
  void observe(double end, const Eigen::Matrix3Xd& positions, const Eigen::Matrix3Xd& forces);

  double tool_displacement() const { return tool_displacement_; }  ///< m, at the last observe
  double tool_force() const { return tool_force_.norm(); }  ///< N, at the last observe
  /// N: the force the tissue exerts on the tool (grasp or instrument), at the last observe.
  const Eigen::Vector3d& tool_force_vector() const { return tool_force_; }
  double max_penetration() const { return max_penetration_; }      ///< m, over all observes
  /// m, over the observes from the instrument's start to its release.
  double max_penetration_pressing() const { return max_penetration_pressing_; }
  int lost_contact_vertices() const;
  /// The most intersecting tissue-instrument triangle pairs of any step, the tissue where the
  /// step started and the instrument where it ended, counted at observe() (outside the step's
  /// timed work: the contact's holds do not use it): the thesis's measure of contact (table
  /// 4.2); 0 while the contact keeps the tissue outside the instrument's margin.
  int max_triangle_pairs() const { return max_triangle_pairs_; }

 private:
  bool grasp_holds(double time) const;
  Eigen::Vector3d tool_origin(double time) const;

  const scenes::Scene& scene_;
  std::vector<PositionConstraint> fixed_;  ///< the fixed region, then the supports (sliding)
  std::vector<int> grasped_;
  Eigen::Matrix3Xd grasp_anchor_;  ///< grasped vertices where grasped: world (grasp) or tool frame
  std::unique_ptr<collision::InstrumentContact> contact_;
  std::vector<PositionConstraint> constraints_;
  std::vector<int> loaded_;           ///< vertices whose constraint forces act on the tool
  std::vector<char> held_;            ///< per vertex: fixed or grasped this step (scratch)
  /// Per vertex: its support's index in fixed_ (and constraints_), or -1.
  std::vector<int> support_slot_;
  std::size_t held_constraints_ = 0;  ///< constraints_ before the contact's: fixed, grasp
  std::size_t held_loaded_ = 0;       ///< loaded_ before the contact's
  Eigen::Isometry3d end_pose_ = Eigen::Isometry3d::Identity();  ///< the instrument this step

  void add_contact_targets();
  static void merge_contact(PositionConstraint& support, const collision::VertexTarget& contact);
  std::vector<bool> in_contact_;  ///< per vertex: pressed by the instrument at the last step
  std::vector<bool> lost_;        ///< per vertex: lost contact while the instrument pressed
  double tool_displacement_ = 0.0;
  Eigen::Vector3d tool_force_ = Eigen::Vector3d::Zero();
  double max_penetration_ = 0.0;
  double max_penetration_pressing_ = 0.0;
  int max_triangle_pairs_ = 0;
};

}  // namespace softbench::harness
