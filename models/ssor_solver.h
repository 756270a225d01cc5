// SPDX-License-Identifier: MIT
#pragma once

#include "models/block_pattern.h"
#include "models/coarse_space.h"
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
/// Two levels: the iterations are deflated by a coarse space W, the translations of aggregates
/// of vertices (CoarseSpace, LinearSolverOptions::coarse_vertices). The start is corrected so
/// that W^T r = 0, and each new direction is made A-orthogonal to W (Saad, Yeung, Erhel and
/// Guyomarc'h 2000: p = z + beta p - W^ mu, E mu = W^^T A^ z, with W^ = (D + U) W and E =
/// W^^T A^ W^ = W^T A W), so every residual stays orthogonal to W: an aggregate's displacement as
/// a whole, which the sweeps smooth slowest and which no stiffness resists on a free body, is
/// solved exactly on the coarse level. The iteration tracks t = (D + U)^-1 p and U t instead of
/// p: t = beta t + s - W mu with s = (D + U)^-1 z from the backward sweep (which also gives
/// U s), W^^T A^ z = (A W)^T s, p . A^ p = t . D t + 2 t . U t, and A^ p = t + (D + L)^-1 U t
/// from the forward sweep; x += alpha t directly. Per iteration: the two sweeps as before (the
/// backward one also sums (A W)^T s), a pass for t and U t over U W's blocks, and a coarse
/// solve.
///
/// With LinearSolverOptions::single_precision_sweeps the sweeps read a copy of the matrix's
/// values rounded to single precision (made at the solve's start), while the diagonal blocks,
/// the start's residual and the coarse level keep the doubles: half the bytes an iteration
/// where the matrix is streamed from memory. CG then solves the rounded matrix for the true
/// residual of the start, so the rounding changes the correction only, by about 6e-8 of it.
class SsorConjugateGradientSolver final : public SystemSolver {
 public:
  SsorConjugateGradientSolver(const LinearSolverOptions& options, const BlockPattern& pattern);

  /// The least tolerance at which the sweeps read the single-precision copy
  /// (LinearSolverOptions::single_precision_sweeps); below it they read the doubles. CG on the
  /// rounded sweeps corrects its start by the rounded matrix's inverse, whose error (the
  /// rounding, 6e-8 of an entry, times the system's conditioning) no tolerance can go below:
  /// asked for 1e-7 on the tests' box, or 1e-8 on liver_x4, the estimate never met it and CG
  /// broke down with the iterate far from the answer (liver_x4's body wrecked in 20 steps).
  /// 1e-6 converged on both (1e-7 on liver_x4): the floor is a factor of 10 above the box's
  /// edge, 100 above liver_x4's, and a thousandth of corotational_fem's default tolerance.
  static constexpr double kSingleSweepsTolerance = 1e-6;

  SolveReport solve(const BlockPattern& a,
                    const Eigen::VectorXd& b,
                    Eigen::VectorXd& x,
                    const double* offset) override;
  std::size_t memory_bytes() const override;

 private:
  /// What a solve needs of the matrix before it iterates: the coarse level (A W, U W, E
  /// factorised), D_c and D_c^-1 of every vertex, and the sweeps' single-precision copy when
  /// they read one. On the threads, E's factorisation (serial) runs beside the vertices' part.
  /// False if a diagonal block is singular or not finite, or E is not positive definite.
  bool load(const BlockPattern& a);
  /// Vertices a thread takes at a time in load()'s loop.
  static constexpr int kVerticesPerBlock = 256;

  LinearSolverOptions options_;
  /// Whether the sweeps read single_values_: asked for, and the tolerance at least
  /// kSingleSweepsTolerance.
  bool single_sweeps_ = false;
  int num_vertices_ = 0;
  std::vector<double> diagonal_;  ///< 9 per vertex, row-major D_c
  std::vector<double> inverse_;   ///< 9 per vertex, D_c^-1
  CoarseSpace coarse_;
  // Work vectors (3 #V), sized once.
  Eigen::VectorXd residual_;         ///< r^
  Eigen::VectorXd preconditioned_;   ///< z = D r^
  Eigen::VectorXd sweep_;            ///< s = (D + U)^-1 z
  Eigen::VectorXd sweep_upper_;      ///< U s
  Eigen::VectorXd direction_;        ///< t = (D + U)^-1 p
  Eigen::VectorXd direction_upper_;  ///< U t
  Eigen::VectorXd forward_;          ///< y = (D + L)^-1 U t; the start product's scratch
  std::vector<double> chunk_sums_;   ///< the reference energy's per-chunk parts
  /// The matrix's values in single precision (LinearSolverOptions::single_precision_sweeps).
  std::vector<float> single_values_;
};

}  // namespace softbench
