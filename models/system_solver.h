// SPDX-License-Identifier: MIT
#pragma once

#include "models/block_pattern.h"

#include <Eigen/Core>

#include <cstddef>
#include <memory>

namespace softbench {

/// How an implicit model solves its symmetric positive definite system each step.
struct LinearSolverOptions {
  enum class Kind {
    /// CHOLMOD supernodal LL^T: symbolic analysis once, a numeric factorisation every step.
    /// Exact (backward stable); its cost is the factorisation, which grows fast with the mesh.
    kCholmod,
    /// Conjugate gradients with the Jacobi (inverse diagonal) preconditioner, warm-started from
    /// the caller's guess, stopping at `tolerance` or `max_iterations`. Cheap per iteration.
    kConjugateGradient,
    /// Conjugate gradients preconditioned by a CHOLMOD factor of an earlier step's matrix,
    /// kept across steps and refactorised (with the current matrix) when a solve needed more
    /// than `refresh_iterations` iterations, or failed to converge (then the solve is redone).
    /// Few iterations while the matrix changes slowly; each costs two triangular solves.
    kCholeskyPcg,
  };
  Kind kind = Kind::kConjugateGradient;
  /// Iterative kinds: stop once the error's energy norm |x - x*|_A, estimated from the CG
  /// coefficients (Hestenes and Stiefel's estimate over the last kErrorDelay iterations, Strakos
  /// and Tichy 2002), is at most `tolerance` times the energy norm of what the solve is for:
  /// |offset + x|_A with the caller's offset (the implicit models pass the velocities, so the
  /// error is relative to the step's new velocity), and never less than the solve's own change
  /// |x - x0|_A. A residual relative to |b| is no such measure: prescribed positions can dominate
  /// b, a warm start can meet it with no iteration while the load has not reached the body, and
  /// on an ill-conditioned system a small residual still allows a large error. Smaller: more
  /// accurate, more iterations.
  double tolerance = 1e-6;
  /// Iterative kinds: cap per solve; a solve that hits it reports iterations == cap.
  int max_iterations = 200;
  /// kCholeskyPcg: refactorise before the next solve when this one needed more iterations.
  int refresh_iterations = 8;
};

/// What one solve of the implicit system cost and how well it did.
struct SolveReport {
  int iterations = 0;     ///< CG iterations (0 for kCholmod)
  double residual = 0.0;  ///< |A x - b| / |b| (|A x - b| when b = 0)
  /// Iterative kinds: the estimated relative energy-norm error at the stop (0 for kCholmod).
  double error = 0.0;
  bool converged = true;  ///< false: an iterative solve hit max_iterations first
  int factorizations = 0;
  bool succeeded = true;  ///< false: a factorization failed (not SPD or not finite) or NaN
};

/// Solves A x = b for a matrix with a fixed BlockPattern whose values change every step.
class SystemSolver {
 public:
  virtual ~SystemSolver() = default;
  SystemSolver(const SystemSolver&) = delete;
  SystemSolver& operator=(const SystemSolver&) = delete;

  /// `x` holds the initial guess on entry (used by iterative solvers) and the solution on exit.
  /// `offset` (b.size() values, or null: none) sets what the iterative stopping rule measures the
  /// error against (LinearSolverOptions::tolerance). Allocates nothing after the first call.
  virtual SolveReport solve(const BlockPattern& a,
                            const Eigen::VectorXd& b,
                            Eigen::VectorXd& x,
                            const double* offset) = 0;
  virtual std::size_t memory_bytes() const = 0;

 protected:
  SystemSolver() = default;
};

/// The solver `options` names; CHOLMOD's symbolic analysis of `pattern` is done here, once.
std::unique_ptr<SystemSolver> make_system_solver(const LinearSolverOptions& options,
                                                 const BlockPattern& pattern);

}  // namespace softbench
