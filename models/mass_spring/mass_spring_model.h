// SPDX-License-Identifier: MIT
#pragma once

#include "geometry/tet_mesh.h"
#include "models/block_pattern.h"
#include "models/implicit_system.h"
#include "models/mass_spring/mass_spring.h"
#include "models/param_table.h"
#include "models/system_solver.h"

#include <Eigen/Core>

#include <memory>
#include <vector>

namespace softbench::mass_spring {

/// The parameter table: reads scene blocks, echoes effective values, documents defaults.
const ParamTable<MassSpringParams>& param_table();

/// Throws InputError naming `where` for a value the table would reject (NaN, negative
/// stiffness, ...): the table's ranges are the only statement of what is valid.
void validate(const MassSpringParams& params, const std::string& where);

/// The model of mass_spring.h. Construction precomputes everything; see step() for the
/// per-step work. StepStats.residual is the CG relative residual, or for CHOLMOD the relative
/// residual |A dv - b| / |b| of the solved (constraint-eliminated) system; 0 for symplectic Euler.
class MassSpringModel final : public SoftBody {
 public:
  MassSpringModel(const TetMesh& mesh, const Material& material, const MassSpringParams& params);

  std::string_view name() const override { return "mass_spring"; }
  nlohmann::json parameters() const override;
  StepStats step(double dt, const StepInput& input) override;
  void reset() override;

  const Eigen::Matrix3Xd& positions() const override { return positions_; }
  const Eigen::Matrix3Xd& velocities() const override { return velocities_; }
  /// Also drops the implicit solve's warm start (the last dv, made for the old velocities).
  void set_velocities(const Eigen::Matrix3Xd& velocities) override;
  void set_state(const Eigen::Matrix3Xd& positions, const Eigen::Matrix3Xd& velocities) override;
  Eigen::Matrix3Xd constraint_forces() const override { return constraint_forces_; }
  double elastic_energy() const override;
  std::size_t memory_bytes() const override;

 private:
  /// Per spring: elastic + dashpot force on its first vertex (the second gets the opposite).
  void compute_spring_forces();
  /// Per spring, for backward Euler: the force plus dt K_e (v_i - v_j), and the block
  /// dt c d d^T + dt^2 k S that the spring adds to A (Baraff & Witkin 1998, section 4).
  void compute_spring_linearization(double dt);
  /// Forces of gravity, external loads, mass damping and penalty constraints on `vertex`.
  Eigen::Vector3d vertex_force(int vertex,
                               const StepInput& input,
                               const PositionConstraint* constraint) const;

  StepStats step_symplectic(double dt, const StepInput& input);
  StepStats step_implicit(double dt, const StepInput& input);
  /// Assembles A and b of (M - dt D - dt^2 K) dv = dt (f + dt K v) into the fixed pattern.
  void assemble_implicit_system(double dt, const StepInput& input);
  /// Moves the known dv of exactly constrained vertices to the right-hand side and makes their
  /// rows and columns identity (ConstraintElimination).
  void eliminate_exact_constraints(double dt);
  /// (A dv - b)_c / dt with the unmodified rows of every exactly constrained vertex.
  void compute_implicit_reactions(double dt);
  StepStats finish_step() const;

  MassSpringParams params_;
  int num_vertices_ = 0;

  // Springs (the unique edges of the tet mesh) and vertices, fixed after construction.
  Eigen::Matrix2Xi springs_;
  Eigen::VectorXd rest_lengths_;
  Eigen::VectorXd spring_stiffness_;
  Eigen::VectorXd masses_;
  Eigen::Matrix3Xd rest_positions_;
  // Springs incident to each vertex (CSR): per-vertex gathers need no atomics, so a parallel
  // loop sums in a fixed order and results do not depend on the thread count.
  std::vector<int> incident_offsets_;
  std::vector<int> incident_springs_;

  // State.
  Eigen::Matrix3Xd positions_;
  Eigen::Matrix3Xd velocities_;
  Eigen::Matrix3Xd constraint_forces_;

  // Per-step work arrays, sized once.
  Eigen::Matrix3Xd spring_forces_;  ///< 3 x #springs, on the first vertex
  Eigen::Matrix3Xd spring_rhs_;     ///< 3 x #springs, f_e + dt K_e (v_i - v_j)
  Eigen::Matrix<double, 9, Eigen::Dynamic> spring_blocks_;  ///< 3x3 blocks, column-major
  VertexConstraints constraints_;                           ///< bound for the duration of one step

  // Implicit Euler only.
  std::unique_ptr<BlockPattern> pattern_;
  std::unique_ptr<SystemSolver> solver_;
  ConstraintElimination elimination_;
  Eigen::Matrix3Xd known_changes_;  ///< dv at exactly constrained vertices (3 x #V)
  Eigen::VectorXd rhs_;
  Eigen::VectorXd velocity_change_;  ///< dv; the previous step's warm-starts CG
};

}  // namespace softbench::mass_spring
