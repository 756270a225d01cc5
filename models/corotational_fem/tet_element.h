// SPDX-License-Identifier: MIT
#pragma once

#include "models/linear_tet.h"
#include "models/material.h"

#include <Eigen/Core>

// The corotational FEM's element kernels on the linear tet of models/linear_tet.h (inline: they
// run once per element per step; Mueller & Gross 2004). Linear isotropic stress
// sigma(eps) = 2 mu eps + lambda tr(eps) I.

namespace softbench::corotational_fem {

/// sigma(eps) = 2 mu eps + lambda tr(eps) I, Pa, for a symmetric strain.
inline Eigen::Matrix3d linear_stress(const Eigen::Matrix3d& strain, const LameParameters& lame) {
  Eigen::Matrix3d stress = (2.0 * lame.mu) * strain;
  stress.diagonal().array() += lame.lambda * strain.trace();
  return stress;
}

/// The corotated strain sym(R^T F) - I (R = I: the small strain of linear FEM).
inline Eigen::Matrix3d corotated_strain(const Eigen::Matrix3d& rotation,
                                        const Eigen::Matrix3d& deformation) {
  const Eigen::Matrix3d unrotated = rotation.transpose() * deformation;
  return 0.5 * (unrotated + unrotated.transpose()) - Eigen::Matrix3d::Identity();
}

/// The stress R sigma(sym(R^T F) - I) (a first Piola-Kirchhoff stress, Pa): the nodal forces
/// are f_a = -V P b_a. With R the polar rotation of F this is the gradient of element_energy's
/// density (the dR terms vanish: R^T F is symmetric and dR = R W with W skew).
inline Eigen::Matrix3d corotated_stress(const Eigen::Matrix3d& rotation,
                                        const Eigen::Matrix3d& deformation,
                                        const LameParameters& lame) {
  return rotation * linear_stress(corotated_strain(rotation, deformation), lame);
}

/// Elastic forces on the 4 nodes (N, columns): f_a = -V R sigma(sym(R^T F) - I) b_a. They sum to
/// zero (b0 = -(b1 + b2 + b3)). R = I gives linear FEM's f = -K (x - X).
inline Matrix34d element_forces(const TetRest& rest,
                                const Eigen::Matrix3d& rotation,
                                const Eigen::Matrix3d& deformation,
                                const LameParameters& lame) {
  return -element_gradient(rest, corotated_stress(rotation, deformation, lame));
}

/// V [mu |S - I|_F^2 + lambda/2 tr(S - I)^2] with S = sym(R^T F), J. With R the polar rotation
/// this is the corotated energy (S the stretch); with R = I, linear FEM's energy.
inline double element_energy(const TetRest& rest,
                             const Eigen::Matrix3d& rotation,
                             const Eigen::Matrix3d& deformation,
                             const LameParameters& lame) {
  const Eigen::Matrix3d strain = corotated_strain(rotation, deformation);
  const double trace = strain.trace();
  return rest.volume * (lame.mu * strain.squaredNorm() + 0.5 * lame.lambda * trace * trace);
}

/// The stiffness block K_ab = -d f_a / d x_b with R held fixed (warped stiffness, Mueller & Gross
/// 2004): R K0_ab R^T = V [lambda c_a c_b^T + mu c_b c_a^T + mu (c_a . c_b) I], c = R b (N/m).
/// K_ba = K_ab^T; each block row sums to zero.
inline Eigen::Matrix3d stiffness_block(const Eigen::Vector3d& rotated_gradient_a,
                                       const Eigen::Vector3d& rotated_gradient_b,
                                       double volume,
                                       const LameParameters& lame) {
  const Eigen::Matrix3d outer = rotated_gradient_a * rotated_gradient_b.transpose();
  Eigen::Matrix3d block = lame.lambda * outer + lame.mu * outer.transpose();
  block.diagonal().array() += lame.mu * rotated_gradient_a.dot(rotated_gradient_b);
  return volume * block;
}

}  // namespace softbench::corotational_fem
