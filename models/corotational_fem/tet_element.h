// SPDX-License-Identifier: MIT
#pragma once

#include "models/material.h"

#include <Eigen/Core>

// One linear (4-node) tetrahedron of the corotational FEM: rest-shape precomputation and the
// element kernels the model's step is built from (inline: they run once per element per step).
//
// Notation (Mueller & Gross 2004; Sifakis & Barbic 2012, "FEM simulation of 3D deformable
// solids", section 4): rest and current node positions X_a, x_a (a = 0..3);
// Dm = [X1-X0, X2-X0, X3-X0], Ds = [x1-x0, x2-x0, x3-x0], deformation gradient F = Ds Dm^-1.
// Shape-function gradients b_a (1/m): [b1 b2 b3] = Dm^-T, b0 = -(b1 + b2 + b3), so
// F = sum_a x_a b_a^T. Linear isotropic stress sigma(eps) = 2 mu eps + lambda tr(eps) I.

namespace softbench::corotational_fem {

using Matrix34d = Eigen::Matrix<double, 3, 4>;

/// What a tet keeps from its rest shape.
struct TetRest {
  Eigen::Matrix3d rest_inverse = Eigen::Matrix3d::Identity();  ///< Dm^-1, 1/m
  double volume = 0.0;                                         ///< V, m^3 (> 0 on a TetMesh)
};

/// Rest data from the 4 rest positions (columns of `rest`, TetMesh orientation).
TetRest tet_rest(const Matrix34d& rest);

/// The 4 shape-function gradients b_a as columns (1/m).
inline Matrix34d shape_gradients(const TetRest& rest) {
  Matrix34d gradients;
  gradients.rightCols<3>() = rest.rest_inverse.transpose();
  gradients.col(0) = -gradients.rightCols<3>().rowwise().sum();
  return gradients;
}

/// F = Ds Dm^-1 of the 4 current positions (columns of `x`).
inline Eigen::Matrix3d deformation_gradient(const TetRest& rest, const Matrix34d& x) {
  Eigen::Matrix3d edges;
  edges.col(0) = x.col(1) - x.col(0);
  edges.col(1) = x.col(2) - x.col(0);
  edges.col(2) = x.col(3) - x.col(0);
  return edges * rest.rest_inverse;
}

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
  const Eigen::Matrix3d stress = (-rest.volume) * corotated_stress(rotation, deformation, lame);
  Matrix34d forces;
  forces.rightCols<3>() = stress * rest.rest_inverse.transpose();
  forces.col(0) = -forces.rightCols<3>().rowwise().sum();
  return forces;
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
