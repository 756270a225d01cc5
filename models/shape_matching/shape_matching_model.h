// SPDX-License-Identifier: MIT
#pragma once

#include "geometry/tet_mesh.h"
#include "models/param_table.h"
#include "models/shape_matching/cluster_matching.h"
#include "models/shape_matching/clusters.h"
#include "models/shape_matching/shape_matching.h"
#include "models/vertex_constraints.h"

#include <Eigen/Core>

#include <span>
#include <string>
#include <vector>

namespace softbench::shape_matching {

/// The parameter table: reads scene blocks, echoes effective values, documents defaults.
const ParamTable<ShapeMatchingParams>& param_table();

/// Throws InputError naming `where` for a value the table would reject.
void validate(const ShapeMatchingParams& params, const std::string& where);

/// The model of shape_matching.h. Construction builds the clusters and the matcher's rest-shape
/// data; step() allocates nothing, but for the held data of a cluster that has held members for
/// the first time (kept for reuse after).
class ShapeMatchingModel final : public SoftBody {
 public:
  ShapeMatchingModel(const TetMesh& mesh,
                     const Material& material,
                     const ShapeMatchingParams& params);

  std::string_view name() const override { return "shape_matching"; }
  nlohmann::json parameters() const override;
  StepStats step(double dt, const StepInput& input) override;
  void reset() override;

  const Eigen::Matrix3Xd& positions() const override { return positions_; }
  const Eigen::Matrix3Xd& velocities() const override { return velocities_; }
  /// A step predicts x + dt v from them; the clusters' warm starts (rotations, centres) depend
  /// on the positions only and are kept.
  void set_velocities(const Eigen::Matrix3Xd& velocities) override;
  void set_state(const Eigen::Matrix3Xd& positions, const Eigen::Matrix3Xd& velocities) override;
  const Eigen::Matrix3Xd& constraint_forces() const override { return constraint_forces_; }
  double elastic_energy() const override;  ///< NaN: shape matching has no energy
  std::size_t memory_bytes() const override;

  /// For tests and reports: the clusters, and the matcher (its goals are those of the last pass
  /// of the last step; with one pass, computed from the predicted positions).
  const Clusters& clusters() const { return clusters_; }
  const ClusterMatcher& matcher() const { return matcher_; }
  /// 3 x #V: the predicted positions x* = x + dt v* of the last step, which the goals matched.
  const Eigen::Matrix3Xd& predicted_positions() const { return predicted_; }

 private:
  /// v* and x* of particles [first, last) (their targets, for exact constraints).
  void predict(int first, int last, double dt, const StepInput& input);
  /// v* and x* of a constrained particle, into flight_ and predicted_, from its state before the
  /// step; an exact constraint's reaction starts here.
  void predict_constrained(int vertex,
                           const PositionConstraint& constraint,
                           double dt,
                           const StepInput& input);
  /// One alpha pull of particles [first, last) toward their goals: moves them and their
  /// velocities, and sums the reactions of exact constraints.
  void pull(int first, int last, double dt);
  /// An exactly held particle's part of a pull: towards_ keeps what its hold leaves free, the
  /// rest is its reaction.
  void pull_held(int vertex, const PositionConstraint& constraint, double dt);
  /// After the last pull: the forces of penalty constraints among particles [first, last).
  void finish(int first, int last);

  ShapeMatchingParams params_;
  int num_vertices_ = 0;
  Eigen::VectorXd masses_;
  Eigen::VectorXd inverse_masses_;
  Eigen::Matrix3Xd rest_positions_;
  double diagonal_ = 1.0;  ///< m, the rest bounding-box diagonal (for the residual)
  Clusters clusters_;
  ClusterMatcher matcher_;

  // State.
  Eigen::Matrix3Xd positions_;
  Eigen::Matrix3Xd velocities_;
  Eigen::Matrix3Xd constraint_forces_;

  // Per-step work arrays, sized once.
  Eigen::Matrix3Xd predicted_;           ///< x*
  Eigen::Matrix3Xd flight_;              ///< v*, while predict() makes it
  Eigen::Matrix3Xd towards_;             ///< a pass's g - x, less what holds deny
  Eigen::VectorXd squared_residuals_;    ///< |g - x*|^2 per particle (0 if exactly held)
  std::vector<int> cluster_iterations_;  ///< rotation iterations per cluster
  VertexConstraints constraints_;        ///< the step's constraint per vertex
  std::vector<int> kinematic_;           ///< the step's fully held vertices (the matcher's held)
};

}  // namespace softbench::shape_matching
