// SPDX-License-Identifier: MIT
#pragma once

#include "models/neo_hookean/stable_neo_hookean.h"

#include <Eigen/Core>

// A linear (4-node) tet of the neo-Hookean model: its rest data and the chain rule from the
// energy density's derivatives in F to derivatives in the 12 node coordinates.
//
// Notation (Sifakis & Barbic 2012, section 4): rest and current node positions X_a, x_a;
// Dm = [X1-X0, X2-X0, X3-X0], F = Ds Dm^-1 = sum_a x_a b_a^T with the shape-function gradients
// [b1 b2 b3] = Dm^-T, b0 = -(b1 + b2 + b3) (1/m). Node coordinates are ordered 3 a + i.

namespace softbench::neo_hookean {

using Matrix34d = Eigen::Matrix<double, 3, 4>;
using Matrix12d = Eigen::Matrix<double, 12, 12>;

/// What a tet keeps from its rest shape.
struct TetRest {
  Eigen::Matrix3d rest_inverse = Eigen::Matrix3d::Identity();  ///< Dm^-1, 1/m
  double volume = 0.0;                                         ///< V, m^3 (> 0 on a TetMesh)
};

/// Rest data from the 4 rest positions (columns, TetMesh orientation: positive volume).
TetRest tet_rest(const Matrix34d& rest);

/// F = Ds Dm^-1 of the 4 current positions (columns of `x`).
inline Eigen::Matrix3d deformation_gradient(const TetRest& rest, const Matrix34d& x) {
  Eigen::Matrix3d edges;
  edges.col(0) = x.col(1) - x.col(0);
  edges.col(1) = x.col(2) - x.col(0);
  edges.col(2) = x.col(3) - x.col(0);
  return edges * rest.rest_inverse;
}

/// d(V Psi)/dx_a = V P b_a as columns (N): the negated elastic forces on the nodes. They sum to
/// zero.
inline Matrix34d element_gradient(const TetRest& rest, const Eigen::Matrix3d& stress) {
  Matrix34d gradient;
  gradient.rightCols<3>() = (rest.volume * stress) * rest.rest_inverse.transpose();
  gradient.col(0) = -gradient.rightCols<3>().rowwise().sum();
  return gradient;
}

/// d^2(V Psi)/dx^2 = V B^T (dP/dF) B (12x12, N/m), B = dvec(F)/dx (9x12, B(3k + i, 3a + i) =
/// b_a(k)). Symmetric; positive semi-definite when `stress_derivative` is.
Matrix12d element_hessian(const TetRest& rest, const Matrix9d& stress_derivative);

}  // namespace softbench::neo_hookean
