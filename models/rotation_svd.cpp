// SPDX-License-Identifier: MIT
#include "models/rotation_svd.h"

#include <Eigen/LU>
#include <Eigen/SVD>

namespace softbench {

RotationSvd rotation_svd(const Eigen::Matrix3d& deformation) {
  const Eigen::JacobiSVD<Eigen::Matrix3d> svd(deformation,
                                              Eigen::ComputeFullU | Eigen::ComputeFullV);
  RotationSvd result{svd.matrixU(), svd.matrixV()};
  if (result.u.determinant() < 0.0) {
    result.u.col(2) = -result.u.col(2);
  }
  if (result.v.determinant() < 0.0) {
    result.v.col(2) = -result.v.col(2);
  }
  return result;
}

}  // namespace softbench
