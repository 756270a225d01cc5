// SPDX-License-Identifier: MIT
#pragma once

#include <Eigen/Core>
#include <Eigen/Geometry>

#include <cmath>
#include <span>

// The rotation of a deformation gradient, F = R S, for the corotational FEM. Two methods:
//
// - rotation_by_svd(): robust and exact (Irving, Teran, Fedkiw 2004, "Invertible finite elements
//   for robust simulation of large deformation", section 5): F = U Sigma V^T, and when det F < 0
//   the reflection is moved onto the smallest singular value, so R = U V^T is always a proper
//   rotation and S = R^T F is symmetric (with one negative eigenvalue for an inverted element).
//   For det F > 0 this is the polar rotation. ~0.5 us per call (Eigen's JacobiSVD).
//
// - extract_rotation(): Mueller, Bender, Chentanez, Macklin 2016, "A robust method to extract the
//   rotational part of deformations" (MIG 2016, algorithm 1). It maximises tr(R^T F) over
//   rotations by the fixed-point iteration q <- dq(w) q with
//   w = sum_i r_i x f_i / (|sum_i r_i . f_i| + 1e-9) (r_i, f_i the columns of R(q) and F). The
//   maximiser of tr(R^T F) over proper rotations is the SVD-with-sign-fix rotation above, so both
//   methods agree where the iteration has converged, inverted elements included. It has no
//   branches or special cases, and warm-started from the previous step's rotation it needs 1-2
//   iterations. dq(w) is the unit quaternion normalize(1, w/2), a rotation about w by
//   2 atan(|w|/2) ~ |w|: the same direction and fixed points as the paper's exp(w) without its
//   sine and cosine.

namespace softbench::corotational_fem {

/// The proper rotation of F by SVD with Irving et al.'s sign fix (det R = +1 always).
Eigen::Matrix3d rotation_by_svd(const Eigen::Matrix3d& deformation);

/// Mueller et al. 2016: improves the unit quaternion `rotation` (the warm start, e.g. the
/// previous step's rotation of the same element) toward the rotation of F. Stops after
/// `max_iterations` updates, or earlier when |w| < `tolerance` (rad, the size of the next
/// update). Returns the number of updates made; `matrix` (if given) receives R(rotation).
/// Inline: the corotational FEM calls it once per element per step.
inline int extract_rotation(const Eigen::Matrix3d& deformation,
                            Eigen::Quaterniond& rotation,
                            int max_iterations,
                            double tolerance,
                            Eigen::Matrix3d* matrix = nullptr) {
  // Guards the division for F ~ 0 (a collapsed element): w -> 0, the rotation is kept.
  constexpr double kDenominatorFloor = 1e-9;
  Eigen::Matrix3d r = rotation.toRotationMatrix();
  int iteration = 0;
  for (; iteration < max_iterations; ++iteration) {
    const Eigen::Vector3d torque = r.col(0).cross(deformation.col(0))
                                   + r.col(1).cross(deformation.col(1))
                                   + r.col(2).cross(deformation.col(2));
    const double alignment = r.col(0).dot(deformation.col(0)) + r.col(1).dot(deformation.col(1))
                             + r.col(2).dot(deformation.col(2));
    // One reciprocal instead of a division per component (here and for the normalisation).
    const Eigen::Vector3d w = torque * (1.0 / (std::abs(alignment) + kDenominatorFloor));
    if (!(w.squaredNorm() >= tolerance * tolerance)) {  // also stops on NaN
      break;
    }
    const Eigen::Vector3d half = 0.5 * w;
    rotation = Eigen::Quaterniond(1.0, half.x(), half.y(), half.z()) * rotation;
    rotation.coeffs() *= 1.0 / rotation.coeffs().norm();
    r = rotation.toRotationMatrix();
  }
  if (matrix != nullptr) {
    *matrix = r;
  }
  return iteration;
}

/// Elements side by side in extract_rotation_lanes(), one per vector lane (two AVX2 vectors of
/// doubles, four SSE2 ones).
inline constexpr int kRotationLanes = 8;

/// extract_rotation() for up to kRotationLanes elements at once, in structure-of-arrays form:
/// `f` and `r` hold column-major 3x3 entries (f[i + 3 j][lane] is F(i, j)); `rotations` (one
/// per used lane, the first rotations.size() lanes) are the warm starts, improved in place, and
/// `r` receives R(q) in every lane (the unused ones' rest at q = 1 whatever their F). Each
/// instruction advances every lane (one element's iteration is a chain of dependent divisions
/// and square roots). The lanes stop together, when every lane's next update is below
/// `tolerance`; until then a lane that has converged still takes its (smaller than tolerance)
/// updates.
void extract_rotation_lanes(const double (&f)[9][kRotationLanes],
                            std::span<Eigen::Quaterniond> rotations,
                            double (&r)[9][kRotationLanes],
                            int max_iterations,
                            double tolerance);

/// extract_rotation_lanes() over many elements, kRotationLanes at a time. `matrices[k]`
/// receives R(rotations[k]). All spans have one entry per element.
void extract_rotations(std::span<const Eigen::Matrix3d> deformations,
                       std::span<Eigen::Quaterniond> rotations,
                       std::span<Eigen::Matrix3d> matrices,
                       int max_iterations,
                       double tolerance);

}  // namespace softbench::corotational_fem
