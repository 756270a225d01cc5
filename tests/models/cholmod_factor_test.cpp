// SPDX-License-Identifier: MIT
// The CHOLMOD factor the implicit models share: its answers, and that it runs on the calling
// thread (the models choose their threads; CHOLMOD's own parallel regions would add threads
// beyond the cores).
#include "models/cholmod_factor.h"

#include <Eigen/Core>
#include <Eigen/SparseCore>
#include <gtest/gtest.h>
#include <omp.h>

#include <filesystem>
#include <random>

namespace softbench {
namespace {

/// The threads this process has now (Linux: its entries in /proc/self/task).
int process_threads() {
  int count = 0;
  for ([[maybe_unused]] const auto& task : std::filesystem::directory_iterator("/proc/self/task")) {
    ++count;
  }
  return count;
}

/// A dense symmetric positive definite n x n matrix, stored sparse (both triangles): its factor
/// is one supernode of n columns, the case where CHOLMOD opens parallel regions of its own.
Eigen::SparseMatrix<double> dense_spd(int n) {
  std::mt19937 random(7);
  std::uniform_real_distribution<double> entry(-1.0, 1.0);
  Eigen::MatrixXd b(n, n);
  for (int j = 0; j < n; ++j) {
    for (int i = 0; i < n; ++i) {
      b(i, j) = entry(random);
    }
  }
  const Eigen::MatrixXd a =
      b * b.transpose() / n + Eigen::MatrixXd::Identity(n, n);  // eigenvalues in [1, ~5]
  return a.sparseView();
}

TEST(CholmodFactor, SolvesALargeSupernodeToRoundOffOnTheCallingThreadAlone) {
  if (!std::filesystem::exists("/proc/self/task")) {
    GTEST_SKIP() << "no /proc/self/task to count the threads by";
  }
  // 700 unknowns, like the coarse level of the largest liver. The OpenMP pool as a one-thread
  // model step leaves it: whatever threads it holds are counted before.
  constexpr int kUnknowns = 700;
  const Eigen::SparseMatrix<double> a = dense_spd(kUnknowns);
  const int team_before = omp_get_max_threads();
  omp_set_num_threads(1);
  const int threads_before = process_threads();

  CholmodFactor factor(a, /*supernodal=*/true);
  ASSERT_TRUE(factor.factorize(a));
  const Eigen::VectorXd expected = Eigen::VectorXd::LinSpaced(kUnknowns, -1.0, 1.0);
  const Eigen::VectorXd b = a * expected;
  Eigen::VectorXd x(kUnknowns);
  factor.solve(b, x);

  // Condition number ~5: the answer to within a few hundred ulps of its size.
  EXPECT_LT((x - expected).lpNorm<Eigen::Infinity>(), 1e-12);
  // No thread was started. Without the guard, CHOLMOD 3's supernodal factorisation of this
  // matrix opened a region of four threads whatever omp_set_num_threads said (on the 2-core
  // machine: two threads more than the one the pool held).
  EXPECT_EQ(process_threads(), threads_before);
  omp_set_num_threads(team_before);
}

}  // namespace
}  // namespace softbench
