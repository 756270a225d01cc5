// SPDX-License-Identifier: MIT
#pragma once

#include "models/block_pattern.h"
#include "models/soft_body.h"
#include "models/vertex_constraints.h"

#include <Eigen/Core>

#include <cstddef>
#include <span>
#include <vector>

// What the implicit models (mass-spring, corotational FEM) share about a step's constraints:
// which constraint acts on each vertex, and exact constraints imposed on a block system A u = b
// by elimination, with the reactions read from the rows as they were before elimination.

namespace softbench {

/// Exact constraints on a symmetric block system A u = b (BlockPattern layout) whose unknown at
/// an exactly constrained vertex c is known, u_c: b_o -= A_oc u_c at every free neighbour o, the
/// rows and columns of c become identity (values only: the pattern keeps its explicit zeros, so
/// CHOLMOD's symbolic analysis stays valid) and b_c = u_c. The system stays symmetric positive
/// definite and its solution is exactly u_c at c. Rows of c are saved first, so
/// constrained_residuals() gives (A u - b)_c of the system as assembled: divided by dt, the force
/// the constraint exerted (the reaction).
///
/// A sliding constraint (PositionConstraint::held of rank 1 or 2) knows u_c along its held
/// directions only. Its vertex's unknowns are first turned into a frame Q_c whose first columns
/// are the held directions (A <- T^T A T, b <- T^T b with T block-diagonal and orthogonal: the
/// same pattern, still symmetric positive definite), then the known coordinates are eliminated
/// as above and the free ones stay unknowns. to_world() turns the solution back; the reaction
/// (A u - b)_c lies along the held directions to the solver's accuracy.
class ConstraintElimination {
 public:
  /// `known` is 3 x #V, read at the exact vertices of `constraints` (along the normal only at a
  /// sliding one). `solution` gets u_c there (also an iterative solver's best guess), in the
  /// eliminated system's frame.
  void eliminate(BlockPattern& pattern,
                 const VertexConstraints& constraints,
                 const Eigen::Matrix3Xd& known,
                 Eigen::VectorXd& rhs,
                 Eigen::VectorXd& solution);

  /// The solved system's unknowns back in the world frame (the sliding vertices' frames undone);
  /// call it after the solve, before reading the solution.
  void to_world(Eigen::VectorXd& solution) const;
  /// A vector added to the unknowns (the solver's offset, 3 #V) in the eliminated system's frame:
  /// `values` itself unless a constraint slides.
  const double* in_frame(const Eigen::Matrix3Xd& values);

  /// (A u - b)_c with the rows saved by the last eliminate(), written to residuals.col(c) for
  /// each exact vertex c (other columns untouched).
  void constrained_residuals(const BlockPattern& pattern,
                             const Eigen::VectorXd& solution,
                             Eigen::Matrix3Xd& residuals) const;

  std::size_t memory_bytes() const;

 private:
  static bool holds_fully(const PositionConstraint* constraint);
  /// Collects the sliding vertices and turns their unknowns into their frames.
  void rotate_sliding(BlockPattern& pattern,
                      const VertexConstraints& constraints,
                      Eigen::VectorXd& rhs,
                      Eigen::VectorXd& solution);

  // Grown to the largest constraint set seen, never shrunk: steady steps do not allocate.
  std::vector<int> vertices_;
  std::vector<int> value_offsets_;    ///< into saved_values_, per saved vertex (+1)
  std::vector<double> saved_values_;  ///< each vertex's three columns (= rows: A is symmetric)
  std::vector<double> saved_rhs_;     ///< 3 per saved vertex
  std::vector<int> sliding_;             ///< the sliding vertices, in elimination order
  std::vector<int> held_counts_;         ///< per sliding vertex: how many directions it holds
  std::vector<Eigen::Matrix3d> frames_;  ///< per sliding vertex: held directions, then free
  Eigen::VectorXd framed_;                ///< in_frame()'s result when a constraint slides
};

/// The velocity change that lands each exact vertex on its target at the end of a step of dt:
/// (target - x) / dt - v, written to changes.col(c) (3 x #V; other columns untouched).
void exact_velocity_changes(const VertexConstraints& constraints,
                            const Eigen::Matrix3Xd& positions,
                            const Eigen::Matrix3Xd& velocities,
                            double dt,
                            Eigen::Matrix3Xd& changes);

/// Backward Euler's update once the velocity change `velocity_change` (3 #V, world frame) is
/// solved: v += dv, x += dt v. An exact vertex lands exactly on its target (a sliding one on its
/// plane) whatever the solver's accuracy on its identity rows, and its dv becomes what moved it
/// there (implicit_reactions reads it).
/// Parallel (OpenMP, static) above BlockPattern::kParallelVertices vertices.
void apply_velocity_change(const VertexConstraints& constraints,
                           double dt,
                           Eigen::VectorXd& velocity_change,
                           Eigen::Matrix3Xd& positions,
                           Eigen::Matrix3Xd& velocities);

/// The constraint forces (3 x #V) after a backward Euler velocity solve: a penalty constraint's
/// spring force at the end of the step (`positions` already updated), an exact one's
/// (A dv - b)_c / dt with the rows as assembled (mass, damping, elastic and gravity terms).
void implicit_reactions(const ConstraintElimination& elimination,
                        const BlockPattern& pattern,
                        const VertexConstraints& constraints,
                        const Eigen::Matrix3Xd& positions,
                        const Eigen::VectorXd& velocity_change,
                        double dt,
                        Eigen::Matrix3Xd& forces);

}  // namespace softbench
