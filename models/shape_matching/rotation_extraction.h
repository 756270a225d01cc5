// SPDX-License-Identifier: MIT
#pragma once

#include <Eigen/Core>
#include <Eigen/Geometry>

namespace softbench::shape_matching {

/// The rotation R of the polar decomposition A = R S (S symmetric), by a 3x3 SVD A = U Sigma V^T:
/// R = U diag(1, 1, det(U V^T)) V^T, the proper rotation nearest to A in the Frobenius norm. For
/// an inverted A (det A < 0) the direction of the smallest singular value is flipped, so R is
/// still a rotation; a rank-deficient or zero A gives some nearest rotation (I for A = 0), and a
/// non-finite A gives I.
Eigen::Matrix3d polar_rotation_svd(const Eigen::Matrix3d& a);

/// Below this correction angle (rad) the quaternion iteration has converged: a few ulps of the
/// rotation matrix.
inline constexpr double kRotationTolerance = 1e-12;

/// Mueller, Bender, Chentanez & Macklin 2016, "A robust method to extract the rotational part of
/// deformations": improves `rotation` (the warm start, e.g. the previous step's) toward the
/// rotational part of `a` by up to `max_iterations` steps of
///   omega = sum_c r_c x a_c / |sum_c r_c . a_c|,  rotation = exp(omega) rotation
/// (r_c, a_c the columns of R(rotation) and of a, scaled to unit norm), stopping early once
/// |omega| < tolerance. Always a unit quaternion, for any finite a (degenerate and inverted
/// included: there it converges to a rotation that locally maximises tr(R^T a)). Returns the
/// number of iterations run; a zero or non-finite `a` leaves `rotation` unchanged.
int extract_rotation(const Eigen::Matrix3d& a,
                     Eigen::Quaterniond& rotation,
                     int max_iterations,
                     double tolerance = kRotationTolerance);

}  // namespace softbench::shape_matching
