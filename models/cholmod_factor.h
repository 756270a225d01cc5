// SPDX-License-Identifier: MIT
#pragma once

#include <Eigen/Core>
#include <Eigen/SparseCore>

#include <cholmod.h>

#include <cstddef>

namespace softbench {

/// A sparse Cholesky factor through CHOLMOD's C API rather than Eigen's wrapper: cholmod_solve2
/// reuses its output and workspace, so a solve allocates nothing after the first of its width
/// (Eigen's solve() allocates twice). Symbolic analysis once, from the pattern given to the
/// constructor; numeric factorisation on demand, of any matrix with that pattern. The matrices
/// are full symmetric (both triangles stored); CHOLMOD reads the lower one without a copy.
class CholmodFactor {
 public:
  /// `supernodal`: BLAS-3 supernodes (large factors, fewer solves) or the simplicial LDL^T,
  /// whose triangular solves are cheaper on small factors solved many times.
  /// `sparsest_ordering`: the analysis tries every fill-reducing ordering CHOLMOD has (AMD,
  /// METIS, its nested dissection, ...) and keeps the sparsest factor, instead of AMD alone: a
  /// slower analysis that pays when one factor serves many solves (on the shipped liver's
  /// scalar Laplacian 53.7k nonzeros in L instead of AMD's 60.0k, on liver_x4 334k instead of
  /// 422k).
  CholmodFactor(const Eigen::SparseMatrix<double>& pattern,
                bool supernodal,
                bool sparsest_ordering = false);
  ~CholmodFactor();
  CholmodFactor(const CholmodFactor&) = delete;
  CholmodFactor& operator=(const CholmodFactor&) = delete;

  /// False when the matrix is not (numerically) positive definite or not finite.
  bool factorize(const Eigen::SparseMatrix<double>& a);

  /// x = A^-1 b with the last factorisation.
  void solve(const Eigen::VectorXd& b, Eigen::VectorXd& x);
  /// X = A^-1 B for `columns` right-hand sides at once (column-major, n x columns): the
  /// triangular factor is read once for all of them.
  void solve(const double* b, int columns, double* x);

  std::size_t memory_bytes() const;

 private:
  cholmod_common common_{};
  cholmod_factor* factor_ = nullptr;
  cholmod_dense* solution_ = nullptr;
  cholmod_dense* workspace_y_ = nullptr;
  cholmod_dense* workspace_e_ = nullptr;
};

}  // namespace softbench
