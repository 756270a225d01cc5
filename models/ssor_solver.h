// SPDX-License-Identifier: MIT
#pragma once

#include "models/block_pattern.h"
#include "models/system_solver.h"

#include <Eigen/Core>

#include <cstddef>
#include <memory>
#include <vector>

namespace softbench {

/// Conjugate gradients preconditioned by symmetric block Gauss-Seidel (SSOR with omega = 1) on a
/// BlockPattern matrix A = L + D + U (D its 3x3 vertex blocks, L and U = L^T the blocks below and
/// above them in vertex order): M = (D + L) D^-1 (D + U). Applied with Eisenstat's trick (1981):
/// CG runs on A^ = (D + L)^-1 A (D + U)^-1 with the preconditioner z = D r, and since
/// A = (D + L) + (D + U) - D, A^ p = t + (D + L)^-1 (p - D t) with t = (D + U)^-1 p: one backward
/// and one forward sweep over the matrix an iteration (each reads half of it), no separate
/// product. |x^ - x^*|_A^ = |x - x*|_A, so the energy-norm stopping rule
/// (LinearSolverOptions::tolerance) reads the same estimate as the Jacobi solver's. CG runs on
/// the correction from the start x0, so x^ starts at 0 and the start costs one forward sweep
/// for r^ = (D + L)^-1 (b - A x0), with A x0 from the caller when it has it (the warm start's
/// products, SystemSolver::set_start_product()): on the liver 4% of corotational_fem's step
/// less than x^ = (D + U) x0 and (D + L)^-1 (b - U x0) from an upper and a lower pass.
///
/// A sweep is a gather over vertex c's columns (the BlockPattern layout: row c of the symmetric
/// matrix is column c), the neighbours before c's own slot for the forward sweep, after it for
/// the backward one. A sweep is sequential (each vertex needs its predecessors'), but not across
/// the pattern's parts (BlockPattern::set_parts(): vertex ranges no block joins, then a
/// separator): forward, the parts side by side and then the separator; backward, the separator
/// and then the parts. The other loops run over the parts and the separator side by side. The
/// order is the vertex numbering's, not the threads', so a solve is bit-identical at any thread
/// count. The corotational FEM numbers its large meshes in parts and measures the solve against
/// Jacobi-PCG per mesh size (its `preconditioner` parameter).
///
/// The solve ends with a coarse correction on the three rigid translations (a two-level
/// method's coarse step, applied once): the error the sweeps leave in a translation, which no
/// stiffness resists, is removed exactly, so a free body keeps its momentum balance.
class SsorConjugateGradientSolver final : public SystemSolver {
 public:
  SsorConjugateGradientSolver(const LinearSolverOptions& options, const BlockPattern& pattern);

  SolveReport solve(const BlockPattern& a,
                    const Eigen::VectorXd& b,
                    Eigen::VectorXd& x,
                    const double* offset) override;
  std::size_t memory_bytes() const override;

 private:
  /// D_c and D_c^-1 of every vertex, (Z^T A)'s block at each vertex (row_sums_) and Z^T A Z
  /// (coarse_) for the three rigid translations Z, in one pass over the matrix's values; false
  /// if a diagonal block is singular or not finite.
  bool load_columns(const BlockPattern& a);

  LinearSolverOptions options_;
  int num_vertices_ = 0;
  std::vector<double> diagonal_;  ///< 9 per vertex, row-major D_c
  std::vector<double> inverse_;   ///< 9 per vertex, D_c^-1
  std::vector<double> row_sums_;  ///< 9 per vertex, column-major: (Z^T A)'s block at the vertex
  Eigen::Matrix3d coarse_;        ///< Z^T A Z
  // Work vectors (3 #V), sized once.
  Eigen::VectorXd residual_;  ///< r^
  Eigen::VectorXd preconditioned_;
  Eigen::VectorXd direction_;
  Eigen::VectorXd product_;
  Eigen::VectorXd sweep_;           ///< t = (D + U)^-1 p
  Eigen::VectorXd carry_;           ///< p - D t, then the forward sweep's y
  Eigen::VectorXd transformed_;     ///< x^ = (D + U) (x - x0)
  std::vector<double> chunk_sums_;  ///< the reference energy's per-chunk parts
};

}  // namespace softbench
