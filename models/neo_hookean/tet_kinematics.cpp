// SPDX-License-Identifier: MIT
#include "models/neo_hookean/tet_kinematics.h"

#include <Eigen/LU>

namespace softbench::neo_hookean {

Matrix12d element_hessian(const TetRest& rest, const Matrix9d& stress_derivative) {
  // Nodes 1..3 first: their block of B is Dm^-T (x) I (B(3k + i, 3(a-1) + i) = Dm^-1(a-1, k)),
  // so their 9x9 block is V (Dm^-1 (x) I) H (Dm^-1 (x) I)^T. Node 0's rows and columns follow
  // from b0 = -(b1 + b2 + b3): minus the block sums. Lazy (coefficient-wise) products: for
  // these fixed sizes they beat Eigen's blocked GEMM path.
  Matrix9d expand;  // Dm^-1 (x) I
  for (int a = 0; a < 3; ++a) {
    for (int k = 0; k < 3; ++k) {
      expand.block<3, 3>(3 * a, 3 * k) = rest.rest_inverse(a, k) * Eigen::Matrix3d::Identity();
    }
  }
  const Matrix9d half = expand.lazyProduct(stress_derivative);
  Matrix9d inner = rest.volume * half.lazyProduct(expand.transpose());
  inner = 0.5 * (inner + inner.transpose()).eval();  // exactly symmetric

  Matrix12d hessian;
  hessian.bottomRightCorner<9, 9>() = inner;
  Eigen::Matrix<double, 3, 9> row_sums = Eigen::Matrix<double, 3, 9>::Zero();
  for (int a = 0; a < 3; ++a) {
    row_sums += inner.middleRows<3>(3 * a);
  }
  hessian.block<3, 9>(0, 3) = -row_sums;
  hessian.block<9, 3>(3, 0) = -row_sums.transpose();
  Eigen::Matrix3d corner = Eigen::Matrix3d::Zero();
  for (int b = 0; b < 3; ++b) {
    corner += row_sums.middleCols<3>(3 * b);
  }
  hessian.topLeftCorner<3, 3>() = corner;
  return hessian;
}

}  // namespace softbench::neo_hookean
