// SPDX-License-Identifier: MIT
#pragma once

#include "models/linear_tet.h"
#include "models/neo_hookean/stable_neo_hookean.h"

#include <Eigen/Core>

// A linear (4-node) tet of the neo-Hookean model: its rest data and the chain rule from the
// energy density's derivatives in F to derivatives in the 12 node coordinates.
//
// Notation (Sifakis & Barbic 2012, section 4): rest and current node positions X_a, x_a;
// Dm = [X1-X0, X2-X0, X3-X0], F = Ds Dm^-1 = sum_a x_a b_a^T with the shape-function gradients
// [b1 b2 b3] = Dm^-T, b0 = -(b1 + b2 + b3) (1/m). Node coordinates are ordered 3 a + i.

namespace softbench::neo_hookean {

using Matrix12d = Eigen::Matrix<double, 12, 12>;

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
