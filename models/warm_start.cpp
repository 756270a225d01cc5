// SPDX-License-Identifier: MIT
#include "models/warm_start.h"

#include <Eigen/Eigenvalues>

#include <algorithm>

namespace softbench {

GalerkinWarmStart::Coefficients GalerkinWarmStart::coefficients(const Gram& gram,
                                                                const Coefficients& projected) {
  Coefficients combination = Coefficients::Zero();
  const Eigen::SelfAdjointEigenSolver<Gram> eigen(gram);
  const double largest = eigen.eigenvalues().cwiseAbs().maxCoeff();
  constexpr double kResolved = 1e-13;  // relative: below it an eigenvalue is round-off
  for (int k = 0; k < kBasis; ++k) {
    const double value = eigen.eigenvalues()(k);
    if (value > kResolved * largest) {
      combination +=
          eigen.eigenvectors().col(k) * (eigen.eigenvectors().col(k).dot(projected) / value);
    }
  }
  return combination.allFinite() ? combination : Coefficients::Zero();
}

GalerkinWarmStart::GalerkinWarmStart(Eigen::Index size) : guess_(size), guess_product_(size) {
  for (Eigen::VectorXd& solution : history_) {
    solution = Eigen::VectorXd::Zero(size);
  }
  for (Eigen::VectorXd& product : products_) {
    product = Eigen::VectorXd::Zero(size);
  }
}

void GalerkinWarmStart::remember(const Eigen::VectorXd& solution) {
  head_ = (head_ + 1) % kBasis;
  history_[static_cast<std::size_t>(head_)] = solution;
  count_ = std::min(count_ + 1, kBasis);
}

std::size_t GalerkinWarmStart::memory_bytes() const {
  return (2 * kBasis + 2) * static_cast<std::size_t>(guess_.size()) * sizeof(double);
}

}  // namespace softbench
