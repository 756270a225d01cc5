// SPDX-License-Identifier: MIT
#pragma once

#include <Eigen/Core>

namespace softbench {

/// F = U S V^T with U and V rotations (det +1), for the models that need F's rotation or its
/// singular values with their sign (corotational FEM, the stable neo-Hookean Hessian, Bullet's
/// corotated energy).
struct RotationSvd {
  Eigen::Matrix3d u;
  Eigen::Matrix3d v;
};

/// Eigen's SVD may leave a reflection in U or V. Negating that factor's column 2, which belongs
/// to the smallest singular value (Eigen sorts them decreasing), moves the reflection into the
/// sign of that singular value instead: U V^T is then the rotation nearest to F, and an inverted
/// element shows as a negative U^T F V entry (2, 2).
RotationSvd rotation_svd(const Eigen::Matrix3d& deformation);

}  // namespace softbench
