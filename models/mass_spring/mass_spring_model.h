// SPDX-License-Identifier: MIT
#pragma once

#include "geometry/tet_mesh.h"
#include "models/block_pattern.h"
#include "models/implicit_system.h"
#include "models/mass_spring/mass_spring.h"
#include "models/mass_spring/spring_system.h"
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

/// Wall time of the phases of an implicit step, accumulated over the steps that were given it (s).
struct PhaseTimes {
  double springs = 0.0;   ///< per spring: length, direction, force, the Jacobian's coefficients
  double assembly = 0.0;  ///< per vertex: forces and right-hand side, diagonal blocks and their
                          ///< inverses; the constraints (CHOLMOD: the matrix and the elimination)
  double solve = 0.0;     ///< the linear solve
  double update = 0.0;    ///< positions, velocities, reactions
};

/// The model of mass_spring.h. Construction precomputes everything; a step allocates nothing
/// (but a constraint set larger than any before, and CHOLMOD's own).
///
/// An implicit step: (1) per spring (parallel over springs from BlockPattern::kParallelVertices
/// vertices), its force, right-hand side part and Jacobian block B_e = u u^T + s I as four
/// numbers; (2) per vertex (parallel likewise, gathering its springs in a fixed order), the
/// right-hand side and the diagonal block with its inverse; (3) the solve: "cg" on the springs'
/// coefficients (SpringSystem, one thread, constraints by filtering), "cholmod" on a BlockPattern
/// assembled from them (constraints by ConstraintElimination); (4) the update and the reactions
/// (each exact vertex's row of the system as assembled). Results do not depend on the thread
/// count.
class MassSpringModel final : public SoftBody {
 public:
  MassSpringModel(const TetMesh& mesh, const Material& material, const MassSpringParams& params);

  std::string_view name() const override { return "mass_spring"; }
  nlohmann::json parameters() const override;
  StepStats step(double dt, const StepInput& input) override { return step_timed(dt, input); }
  /// step(), adding the wall time of an implicit step's phases to `times` (when not null).
  StepStats step_timed(double dt, const StepInput& input, PhaseTimes* times = nullptr);
  void reset() override;

  const Eigen::Matrix3Xd& positions() const override { return positions_; }
  const Eigen::Matrix3Xd& velocities() const override { return velocities_; }
  /// Also drops the implicit solve's warm start (the last dv, made for the old velocities).
  void set_velocities(const Eigen::Matrix3Xd& velocities) override;
  void set_state(const Eigen::Matrix3Xd& positions, const Eigen::Matrix3Xd& velocities) override;
  const Eigen::Matrix3Xd& constraint_forces() const override { return constraint_forces_; }
  double elastic_energy() const override;
  std::size_t memory_bytes() const override;

 private:
  /// Per spring: elastic + dashpot force on its first vertex (the second gets the opposite).
  void compute_spring_forces();
  /// Per spring, for backward Euler: the force plus dt K_e (v_i - v_j), and the block
  /// dt c d d^T + dt^2 k S that the spring adds to A (Baraff & Witkin 1998, section 4), as
  /// SpringSystem's coefficients.
  void compute_spring_linearization(double dt);
  /// Forces of gravity, external loads, mass damping and penalty constraints on `vertex`.
  Eigen::Vector3d vertex_force(int vertex,
                               const StepInput& input,
                               const PositionConstraint* constraint) const;

  StepStats step_symplectic(double dt, const StepInput& input);
  StepStats step_implicit(double dt, const StepInput& input, PhaseTimes* times);
  /// b of (M - dt D - dt^2 K) dv = dt (f + dt K v), and the system's vertex terms.
  void assemble_implicit_system(double dt, const StepInput& input);
  /// CHOLMOD: A from the springs' coefficients into the pattern, b into cholmod_rhs_, the exact
  /// constraints eliminated, the solve.
  SolveReport solve_cholmod();
  /// The constraint forces: penalty springs' at the end of the step, exact constraints'
  /// (A dv - b)_c / dt along their held directions, from the rows as assembled.
  void compute_implicit_reactions(double dt);
  StepStats finish_step() const;
  void drop_warm_start();

  MassSpringParams params_;
  int num_vertices_ = 0;

  // Springs (the unique edges of the tet mesh, sorted) and vertices, fixed after construction.
  Eigen::Matrix2Xi springs_;
  Eigen::VectorXd rest_lengths_;
  Eigen::VectorXd spring_stiffness_;
  Eigen::VectorXd spring_damping_;  ///< damping + rayleigh_stiffness * k_e
  Eigen::VectorXd masses_;
  Eigen::Matrix3Xd rest_positions_;
  double total_mass_ = 0.0;  ///< kg, and the rest bounding-box diagonal (m): the iterative
  double rest_size_ = 0.0;   ///< solve's floor at rest (resting_energy())
  // The system's springs and vertex blocks, and the springs incident to each vertex (CSR):
  // per-vertex gathers need no atomics, so a parallel loop sums in a fixed order and results
  // do not depend on the thread count.
  SpringSystem system_;

  // State.
  Eigen::Matrix3Xd positions_;
  Eigen::Matrix3Xd velocities_;
  Eigen::Matrix3Xd constraint_forces_;

  // Per-step work arrays, sized once.
  Eigen::Matrix3Xd spring_forces_;  ///< 3 x #springs, on the first vertex
  Eigen::Matrix3Xd spring_rhs_;     ///< 3 x #springs, f_e + dt K_e (v_i - v_j)
  VertexConstraints constraints_;   ///< bound for the duration of one step

  // Implicit Euler only.
  Eigen::Matrix3Xd known_changes_;   ///< dv at exactly constrained vertices (3 x #V)
  Eigen::VectorXd rhs_;              ///< b, as assembled
  Eigen::VectorXd velocity_change_;  ///< dv (the solve keeps the last ones for its warm start)
  // CHOLMOD only: the assembled matrix, its solver and the constraint elimination.
  std::unique_ptr<BlockPattern> pattern_;
  std::unique_ptr<SystemSolver> solver_;
  ConstraintElimination elimination_;
  Eigen::VectorXd cholmod_rhs_;
};

}  // namespace softbench::mass_spring
