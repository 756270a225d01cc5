// SPDX-License-Identifier: MIT
#pragma once

#include "models/material.h"

#include <Eigen/Core>

// The stable neo-Hookean energy density of Smith, de Goes and Kim 2018 ("Stable Neo-Hookean
// Flesh Simulation", ACM TOG 37(2), eq. 14), as a function of the deformation gradient F:
//
//     Psi(F) = mu/2 (I_C - 3) + lambda/2 (J - alpha)^2 - mu/2 log(I_C + 1) - Psi(I),
//     I_C = |F|_F^2 = tr(F^T F),  J = det F,  alpha = 1 + 3 mu / (4 lambda),
//
// shifted by the constant Psi(I) so that the rest state has zero energy. alpha makes the rest
// state stress free (P(I) = mu (1 - 1/4) I + lambda (1 - alpha) I = 0). Psi is smooth for every
// F, including J <= 0 (inverted elements keep a finite energy and a restoring force; there is
// no log J), which is why it serves as the converged reference.
//
// Lame reparametrisation (the paper's section 3.4): linearised at F = I, Psi is linear
// elasticity with shear modulus 3 mu / 4 and first Lame parameter lambda - 5 mu / 8. So from the
// material's (lambda_L, mu_L) (material.h, i.e. E and nu):
//     mu = 4/3 mu_L,   lambda = lambda_L + 5/6 mu_L,
// and Psi agrees with E and nu at small strain (tests/models/neo_hookean_test.cpp checks it).
//
// Layout: vec(F) is column-major, entry 3 k + i = F(i, k); the 9x9 Hessians d^2 Psi / dF^2 use
// the same order (entry (3 k + i, 3 l + j) = d^2 Psi / dF_ik dF_jl).

namespace softbench::neo_hookean {

using Matrix9d = Eigen::Matrix<double, 9, 9>;
using Vector9d = Eigen::Matrix<double, 9, 1>;

/// The energy's own parameters (Pa, Pa, dimensionless), not the material's Lame parameters.
struct StableNeoHookean {
  double mu = 0.0;      ///< Pa, 4/3 of the material's shear modulus
  double lambda = 0.0;  ///< Pa, the material's lambda + 5/6 of its shear modulus
  double alpha = 1.0;   ///< 1 + 3 mu / (4 lambda): the rest state is stress free
};

/// The reparametrisation above: matches the material's E and nu at small strain.
StableNeoHookean stable_neo_hookean(const LameParameters& lame);

/// Psi(F) - Psi(I), J/m^3. Evaluated so that its first-order terms cancel exactly for a rotation
/// (through the Green strain, when |J - 1| < 1/2): a rigidly moved element gets ~mu |E|^2 with E
/// the round-off strain, not ~mu 1e-16, so energy differences stay meaningful in a line search.
double energy_density(const Eigen::Matrix3d& deformation, const StableNeoHookean& law);

/// The first Piola-Kirchhoff stress P = dPsi/dF = mu (1 - 1/(I_C + 1)) F + lambda (J - alpha)
/// cof(F), Pa; cof(F) = dJ/dF has the columns f1 x f2, f2 x f0, f0 x f1.
Eigen::Matrix3d first_piola(const Eigen::Matrix3d& deformation, const StableNeoHookean& law);

/// d^2 Psi / dF^2 (9x9, symmetric, Pa): mu (1 - 1/(I_C + 1)) I + 2 mu / (I_C + 1)^2 f f^T
/// + lambda g g^T + lambda (J - alpha) d^2J/dF^2, f = vec(F), g = vec(cof F). Indefinite in
/// general (compression, inversion).
Matrix9d stress_derivative(const Eigen::Matrix3d& deformation, const StableNeoHookean& law);

/// The nearest positive semi-definite matrix (Frobenius norm) to the symmetric `hessian`: its
/// eigendecomposition with negative eigenvalues clamped to zero. A matrix that a Cholesky
/// factorisation accepts (already positive definite) is returned unchanged, skipping the
/// eigensolve. Projecting the 9x9 dP/dF rather than the 12x12 element Hessian is enough: the
/// element Hessian is V B^T (dP/dF) B, which is PSD whenever dP/dF is, and costs a 9x9 solve.
Matrix9d project_to_psd(const Matrix9d& hessian);

/// project_to_psd(stress_derivative(F)), computed in the frame of F's singular vectors, where
/// the isotropic energy's 9x9 eigenproblem splits into one 3x3 and three 2x2 problems (the
/// structure of Smith, de Goes & Kim's analytic eigensystems): ~2x cheaper than the 9x9
/// eigensolve on the liver, the same matrix up to round-off (tested). What the model uses.
Matrix9d projected_stress_derivative(const Eigen::Matrix3d& deformation,
                                     const StableNeoHookean& law);

}  // namespace softbench::neo_hookean
