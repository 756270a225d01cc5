// SPDX-License-Identifier: MIT
#pragma once

#include <Eigen/Core>

// The linear (4-node) tetrahedron every tet FEM model here is built on: rest data, the
// shape-function gradients and the deformation gradient.
//
// Notation (Sifakis & Barbic 2012, "FEM simulation of 3D deformable solids", section 4): rest
// and current node positions X_a, x_a (a = 0..3); Dm = [X1-X0, X2-X0, X3-X0],
// Ds = [x1-x0, x2-x0, x3-x0], F = Ds Dm^-1 = sum_a x_a b_a^T with the shape-function gradients
// [b1 b2 b3] = Dm^-T, b0 = -(b1 + b2 + b3) (1/m).

namespace softbench {

using Matrix34d = Eigen::Matrix<double, 3, 4>;

/// What a tet keeps from its rest shape.
struct TetRest {
  Eigen::Matrix3d rest_inverse = Eigen::Matrix3d::Identity();  ///< Dm^-1, 1/m
  double volume = 0.0;                                         ///< V, m^3 (> 0 on a TetMesh)
};

/// Rest data from the 4 rest positions (columns of `rest`, TetMesh orientation).
TetRest tet_rest(const Matrix34d& rest);

/// The 4 positions of tet t (columns).
inline Matrix34d tet_positions(const Eigen::Matrix3Xd& positions,
                               const Eigen::Matrix4Xi& tets,
                               int t) {
  Matrix34d x;
  for (int a = 0; a < 4; ++a) {
    x.col(a) = positions.col(tets(a, t));
  }
  return x;
}

/// The 4 shape-function gradients b_a as columns (1/m).
inline Matrix34d shape_gradients(const TetRest& rest) {
  Matrix34d gradients;
  gradients.rightCols<3>() = rest.rest_inverse.transpose();
  gradients.col(0) = -gradients.rightCols<3>().rowwise().sum();
  return gradients;
}

/// d(V Psi)/dx_a = V P b_a as columns (N) for the first Piola-Kirchhoff stress P (Pa) of an
/// energy density Psi: the negated elastic forces on the nodes. They sum to zero.
inline Matrix34d element_gradient(const TetRest& rest, const Eigen::Matrix3d& stress) {
  Matrix34d gradient;
  gradient.rightCols<3>() = (rest.volume * stress) * rest.rest_inverse.transpose();
  gradient.col(0) = -gradient.rightCols<3>().rowwise().sum();
  return gradient;
}

/// F = Ds Dm^-1 of the 4 current positions (columns of `x`).
inline Eigen::Matrix3d deformation_gradient(const TetRest& rest, const Matrix34d& x) {
  Eigen::Matrix3d edges;
  edges.col(0) = x.col(1) - x.col(0);
  edges.col(1) = x.col(2) - x.col(0);
  edges.col(2) = x.col(3) - x.col(0);
  return edges * rest.rest_inverse;
}

}  // namespace softbench
