// SPDX-License-Identifier: MIT
#pragma once

#include "models/mass_spring/mass_spring.h"

#include <Eigen/Core>
#include <Eigen/SparseCore>

#include <cstddef>
#include <memory>

namespace softbench::mass_spring {

/// What one solve of the implicit system cost and how well it did.
struct SolveReport {
  int iterations = 0;
  double residual = 0.0;  ///< |A x - b| / |b| (0 when b = 0)
  int factorizations = 0;
  bool succeeded = true;  ///< false: the factorization failed (the matrix was not SPD or finite)
};

/// Solves the symmetric positive definite system of a backward Euler step, A dv = b, for a
/// matrix whose pattern never changes (only its values, every step).
class SystemSolver {
 public:
  virtual ~SystemSolver() = default;
  SystemSolver(const SystemSolver&) = delete;
  SystemSolver& operator=(const SystemSolver&) = delete;

  /// `x` holds the initial guess on entry (used by iterative solvers) and the solution on exit.
  virtual SolveReport solve(const Eigen::SparseMatrix<double>& a,
                            const Eigen::VectorXd& b,
                            Eigen::VectorXd& x) = 0;
  virtual std::size_t memory_bytes() const = 0;

 protected:
  SystemSolver() = default;
};

/// CHOLMOD's supernodal LL^T (symbolic analysis of `pattern` done here, once) or Jacobi-PCG.
std::unique_ptr<SystemSolver> make_system_solver(const MassSpringParams& params,
                                                 const Eigen::SparseMatrix<double>& pattern);

}  // namespace softbench::mass_spring
