// SPDX-License-Identifier: MIT
#pragma once

#include "models/linear_tet.h"
#include "models/material.h"

#include <Eigen/Core>

// The corotational FEM's element energy on the linear tet of models/linear_tet.h (Mueller & Gross
// 2004), linear isotropic stress sigma(eps) = 2 mu eps + lambda tr(eps) I on the corotated strain.
// Its forces and stiffness, a step's kernels, are computed element batch by element batch in
// corotational_fem_terms.cpp and gathered in corotational_fem_step.cpp.

namespace softbench::corotational_fem {

/// The corotated strain sym(R^T F) - I (R = I: the small strain of linear FEM).
inline Eigen::Matrix3d corotated_strain(const Eigen::Matrix3d& rotation,
                                        const Eigen::Matrix3d& deformation) {
  const Eigen::Matrix3d unrotated = rotation.transpose() * deformation;
  return 0.5 * (unrotated + unrotated.transpose()) - Eigen::Matrix3d::Identity();
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

}  // namespace softbench::corotational_fem
