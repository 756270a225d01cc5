// SPDX-License-Identifier: MIT
#pragma once

#include "models/linear_tet.h"
#include "models/neo_hookean/stable_neo_hookean.h"

#include <Eigen/Core>

// The second-order chain rule of the neo-Hookean model's linear tet, from dP/dF to the 12 node
// coordinates (ordered 3 a + i; notation of models/linear_tet.h, whose element_gradient is the
// first-order one).

namespace softbench::neo_hookean {

using Matrix12d = Eigen::Matrix<double, 12, 12>;

/// d^2(V Psi)/dx^2 = V B^T (dP/dF) B (12x12, N/m), B = dvec(F)/dx (9x12, B(3k + i, 3a + i) =
/// b_a(k)). Symmetric; positive semi-definite when `stress_derivative` is.
Matrix12d element_hessian(const TetRest& rest, const Matrix9d& stress_derivative);

}  // namespace softbench::neo_hookean
