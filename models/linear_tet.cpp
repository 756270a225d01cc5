// SPDX-License-Identifier: MIT
#include "models/linear_tet.h"

#include <Eigen/LU>

namespace softbench {

TetRest tet_rest(const Matrix34d& rest) {
  Eigen::Matrix3d edges;
  edges.col(0) = rest.col(1) - rest.col(0);
  edges.col(1) = rest.col(2) - rest.col(0);
  edges.col(2) = rest.col(3) - rest.col(0);
  TetRest result;
  result.volume = edges.determinant() / 6.0;
  // A TetMesh guarantees a positive, non-negligible volume, so Dm is invertible.
  result.rest_inverse = edges.inverse();
  return result;
}

}  // namespace softbench
