// SPDX-License-Identifier: MIT
#include "models/cholmod_factor.h"

#include "models/blas_threads.h"

#include <omp.h>

#include <cstring>

namespace softbench {
namespace {

/// The lower triangle of the full symmetric matrix, without a copy (stype -1 ignores the rest).
cholmod_sparse view_of(const Eigen::SparseMatrix<double>& a) {
  cholmod_sparse view{};
  view.nrow = static_cast<std::size_t>(a.rows());
  view.ncol = static_cast<std::size_t>(a.cols());
  view.nzmax = static_cast<std::size_t>(a.nonZeros());
  view.p = const_cast<int*>(a.outerIndexPtr());  // CHOLMOD only reads them
  view.i = const_cast<int*>(a.innerIndexPtr());
  view.x = const_cast<double*>(a.valuePtr());
  view.stype = -1;
  view.itype = CHOLMOD_INT;
  view.xtype = CHOLMOD_REAL;
  view.dtype = CHOLMOD_DOUBLE;
  view.sorted = 1;
  view.packed = 1;
  return view;
}

/// CHOLMOD's own OpenMP regions run on the calling thread while this lives. Debian's CHOLMOD
/// clears and assembles a large supernode in a parallel region with a fixed thread count of its
/// own (four), which no omp_set_num_threads() bounds: on the 2-core machine each of the coarse
/// level's factorisations on liver_x16 (684 unknowns, one dense supernode) woke three more
/// threads than the cores, on one thread too, and the step waited on them (futex waits 8% of
/// its time, the extra threads 5% of its CPU). The models' loops decide the threads; a region
/// nested in none is serial when no level may be active.
class SerialOpenMp {
 public:
  SerialOpenMp() : levels_(omp_get_max_active_levels()) { omp_set_max_active_levels(0); }
  ~SerialOpenMp() { omp_set_max_active_levels(levels_); }
  SerialOpenMp(const SerialOpenMp&) = delete;
  SerialOpenMp& operator=(const SerialOpenMp&) = delete;

 private:
  int levels_;
};

}  // namespace

CholmodFactor::CholmodFactor(const Eigen::SparseMatrix<double>& pattern,
                             bool supernodal,
                             bool sparsest_ordering) {
  pin_blas_threads();  // the same bits at any thread count
  cholmod_start(&common_);
  common_.print = 0;  // failures are reported by factorize(), not on stderr
  common_.supernodal = supernodal ? CHOLMOD_SUPERNODAL : CHOLMOD_SIMPLICIAL;
  common_.final_asis = 1;
  common_.quick_return_if_not_posdef = 1;
  if (sparsest_ordering) {
    common_.nmethods = CHOLMOD_MAXMETHODS;  // every ordering CHOLMOD has; the sparsest L wins
  }
  cholmod_sparse view = view_of(pattern);
  const SerialOpenMp serial;
  factor_ = cholmod_analyze(&view, &common_);
}

CholmodFactor::~CholmodFactor() {
  cholmod_free_factor(&factor_, &common_);
  cholmod_free_dense(&solution_, &common_);
  cholmod_free_dense(&workspace_y_, &common_);
  cholmod_free_dense(&workspace_e_, &common_);
  cholmod_finish(&common_);
}

bool CholmodFactor::factorize(const Eigen::SparseMatrix<double>& a) {
  if (factor_ == nullptr) {
    return false;
  }
  cholmod_sparse view = view_of(a);
  const SerialOpenMp serial;
  const int ok = cholmod_factorize(&view, factor_, &common_);
  return ok != 0 && common_.status == CHOLMOD_OK && factor_->minor == factor_->n;
}

void CholmodFactor::solve(const Eigen::VectorXd& b, Eigen::VectorXd& x) {
  solve(b.data(), 1, x.data());
}

void CholmodFactor::solve(const double* b, int columns, double* x) {
  cholmod_dense rhs{};
  rhs.nrow = factor_->n;
  rhs.ncol = static_cast<std::size_t>(columns);
  rhs.nzmax = rhs.nrow * rhs.ncol;
  rhs.d = rhs.nrow;
  rhs.x = const_cast<double*>(b);  // read only
  rhs.xtype = CHOLMOD_REAL;
  rhs.dtype = CHOLMOD_DOUBLE;
  const SerialOpenMp serial;
  cholmod_solve2(CHOLMOD_A, factor_, &rhs, nullptr, &solution_, nullptr, &workspace_y_,
                 &workspace_e_, &common_);
  std::memcpy(x, solution_->x, rhs.nzmax * sizeof(double));
}

std::size_t CholmodFactor::memory_bytes() const {
  // Nonzeros of L as the analysis predicts them (values and row indices).
  return static_cast<std::size_t>(common_.lnz) * (sizeof(double) + sizeof(int));
}

}  // namespace softbench
