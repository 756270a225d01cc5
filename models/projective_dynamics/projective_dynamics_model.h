// SPDX-License-Identifier: MIT
#pragma once

#include "geometry/tet_mesh.h"
#include "models/cholmod_factor.h"
#include "models/linear_tet.h"
#include "models/param_table.h"
#include "models/projective_dynamics/held_rows.h"
#include "models/projective_dynamics/projective_dynamics.h"
#include "models/vertex_constraints.h"

#include <Eigen/Core>
#include <Eigen/Geometry>
#include <Eigen/SparseCore>

#include <memory>
#include <string>
#include <vector>

namespace softbench::projective_dynamics {

/// The parameter table: reads scene blocks, echoes effective values, documents defaults.
const ParamTable<ProjectiveDynamicsParams>& param_table();

/// Throws InputError naming `where` for a value the table would reject.
void validate(const ProjectiveDynamicsParams& params, const std::string& where);

/// The model of projective_dynamics.h. Construction builds the constant part of the global
/// matrix and its symbolic analysis; the numeric factorisation waits for the first step's dt
/// and anchored set.
class ProjectiveDynamicsModel final : public SoftBody {
 public:
  ProjectiveDynamicsModel(const TetMesh& mesh,
                          const Material& material,
                          const ProjectiveDynamicsParams& params);

  std::string_view name() const override { return "projective_dynamics"; }
  nlohmann::json parameters() const override;
  StepStats step(double dt, const StepInput& input) override;
  void reset() override;

  const Eigen::Matrix3Xd& positions() const override { return positions_; }
  const Eigen::Matrix3Xd& velocities() const override { return velocities_; }
  void set_velocities(const Eigen::Matrix3Xd& velocities) override;
  void set_state(const Eigen::Matrix3Xd& positions, const Eigen::Matrix3Xd& velocities) override;
  const Eigen::Matrix3Xd& constraint_forces() const override { return constraint_forces_; }
  /// corotational_fem's energy (the same material), with the exact polar rotation (SVD).
  double elastic_energy() const override;
  std::size_t memory_bytes() const override;

 private:
  /// Refactorises A when dt or the set of eliminated (anchoring full exact) holds changed.
  /// False if the factorisation failed.
  bool update_factor(double dt, int* factorizations);
  /// The local step at x: per tet F, R and the projections' parts of b.
  void project_elements(const Eigen::Matrix3Xd& x);
  /// b - A x at x (minus the incremental potential's gradient), the eliminated vertices' rows
  /// replaced by their moves to the targets.
  void assemble_rhs(const Eigen::Matrix3Xd& x);

  ProjectiveDynamicsParams params_;
  LameParameters lame_;
  int num_vertices_ = 0;
  int num_elements_ = 0;

  // Mesh and elements, fixed after construction.
  Eigen::Matrix4Xi tets_;
  Eigen::VectorXd masses_;
  Eigen::Matrix3Xd rest_positions_;
  double rest_size_ = 0.0;
  std::vector<TetRest> elements_;
  std::vector<int> vertex_offsets_;  ///< CSR per vertex: element * 4 + local index
  std::vector<int> vertex_incidences_;
  Eigen::SparseMatrix<double> laplacian_;  ///< sum (w_s + w_v) G^T G (#V x #V, both triangles)

  // The factor and what it was made for.
  Eigen::SparseMatrix<double> system_;  ///< A with the eliminated rows and columns identity's
  std::unique_ptr<CholmodFactor> factor_;
  double factored_dt_ = 0.0;
  std::vector<char> eliminated_;  ///< per vertex: eliminated in the factor
  std::vector<int> eliminated_list_;
  std::vector<char> wanted_;  ///< scratch: this step's eliminated set
  HeldRows held_rows_;

  // State.
  Eigen::Matrix3Xd positions_;
  Eigen::Matrix3Xd velocities_;
  Eigen::Matrix3Xd constraint_forces_;
  std::vector<Eigen::Quaterniond> quaternions_;  ///< per tet, the rotation's warm start

  // Per-step work arrays, sized once.
  VertexConstraints constraints_;
  std::vector<const PositionConstraint*> multiplier_holds_;
  std::vector<Eigen::Matrix3d> deformations_;
  std::vector<Eigen::Matrix3d> rotations_;
  std::vector<Matrix34d> element_parts_;  ///< per tet, its nodes' parts (parallel local step)
  Eigen::Matrix3Xd element_sums_;         ///< per vertex, the elements' parts of the gradient
  Eigen::Matrix3Xd inertia_;              ///< M (y / dt^2 + alpha x_n / dt), N
  Eigen::Matrix3Xd iterate_;              ///< x during the iterations
  Eigen::Matrix3Xd previous_;             ///< the iterate before (Chebyshev, the residual)
  Eigen::Matrix3Xd next_;
  Eigen::Matrix3Xd eliminated_gradients_;  ///< the gradient at each eliminated vertex
  Eigen::Matrix3Xd eliminated_targets_;    ///< the step's target of each eliminated vertex
  Eigen::MatrixX3d rhs_;                   ///< b, #V x 3
  Eigen::MatrixX3d solution_;
  double mass_coefficient_ = 0.0;  ///< 1/dt^2 + alpha/dt
};

}  // namespace softbench::projective_dynamics
