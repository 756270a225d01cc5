// SPDX-License-Identifier: MIT
#include "models/mass_spring/system_solver.h"

// GCC 12's -Wnull-dereference fires inside Eigen's inlined sparse Ref (a matrix's outer index
// pointer it cannot prove non-null), not in this file's code; the rest of the build keeps it.
#pragma GCC diagnostic ignored "-Wnull-dereference"

#include <Eigen/CholmodSupport>
#include <Eigen/IterativeLinearSolvers>

#include <limits>

namespace softbench::mass_spring {
namespace {

using SparseMatrix = Eigen::SparseMatrix<double>;

double relative(double residual_norm, double rhs_norm) {
  return rhs_norm > 0.0 ? residual_norm / rhs_norm : residual_norm;
}

/// A fresh numeric factorisation every step (the values change), on the one symbolic analysis.
class CholmodSolver final : public SystemSolver {
 public:
  explicit CholmodSolver(const SparseMatrix& pattern) : residual_(pattern.rows()) {
    cholesky_.analyzePattern(pattern);
    // Nonzeros of L as the analysis predicts them, for memory_bytes().
    factor_nonzeros_ = cholesky_.cholmod().lnz;
  }

  SolveReport solve(const SparseMatrix& a, const Eigen::VectorXd& b, Eigen::VectorXd& x) override {
    SolveReport report;
    cholesky_.factorize(a);
    report.factorizations = 1;
    if (cholesky_.info() != Eigen::Success) {
      x.setConstant(std::numeric_limits<double>::quiet_NaN());
      report.succeeded = false;
      report.residual = std::numeric_limits<double>::quiet_NaN();
      return report;
    }
    x = cholesky_.solve(b);
    residual_.noalias() = a * x;
    residual_ -= b;
    report.residual = relative(residual_.norm(), b.norm());
    return report;
  }

  std::size_t memory_bytes() const override {
    return static_cast<std::size_t>(factor_nonzeros_) * (sizeof(double) + sizeof(int))
           + static_cast<std::size_t>(residual_.size()) * sizeof(double);
  }

 private:
  Eigen::CholmodSupernodalLLT<SparseMatrix, Eigen::Lower> cholesky_;
  Eigen::VectorXd residual_;
  double factor_nonzeros_ = 0.0;
};

/// Jacobi-preconditioned CG on the full symmetric matrix, warm-started from the caller's guess
/// (the previous step's dv, which changes little between steps).
class ConjugateGradientSolver final : public SystemSolver {
 public:
  ConjugateGradientSolver(double tolerance, int max_iterations, Eigen::Index size) : size_(size) {
    cg_.setTolerance(tolerance);
    cg_.setMaxIterations(max_iterations);
  }

  SolveReport solve(const SparseMatrix& a, const Eigen::VectorXd& b, Eigen::VectorXd& x) override {
    cg_.compute(a);
    x = cg_.solveWithGuess(b, x);
    SolveReport report;
    report.iterations = static_cast<int>(cg_.iterations());
    report.residual = cg_.error();
    return report;
  }

  std::size_t memory_bytes() const override {
    // The Jacobi preconditioner's inverse diagonal and CG's four work vectors.
    return 5 * static_cast<std::size_t>(size_) * sizeof(double);
  }

 private:
  Eigen::ConjugateGradient<SparseMatrix,
                           Eigen::Lower | Eigen::Upper,
                           Eigen::DiagonalPreconditioner<double>>
      cg_;
  Eigen::Index size_;
};

}  // namespace

std::unique_ptr<SystemSolver> make_system_solver(const MassSpringParams& params,
                                                 const SparseMatrix& pattern) {
  if (params.solver == MassSpringParams::LinearSolver::kCholmod) {
    return std::make_unique<CholmodSolver>(pattern);
  }
  return std::make_unique<ConjugateGradientSolver>(params.cg_tolerance, params.cg_max_iterations,
                                                   pattern.rows());
}

}  // namespace softbench::mass_spring
