// SPDX-License-Identifier: MIT
#include "models/shape_matching/rotation_extraction.h"

#include <Eigen/SVD>

#include <cmath>

namespace softbench::shape_matching {

Eigen::Matrix3d polar_rotation_svd(const Eigen::Matrix3d& a) {
  if (!a.allFinite()) {
    return Eigen::Matrix3d::Identity();
  }
  const Eigen::JacobiSVD<Eigen::Matrix3d> svd(a, Eigen::ComputeFullU | Eigen::ComputeFullV);
  Eigen::Matrix3d u = svd.matrixU();
  const Eigen::Matrix3d& v = svd.matrixV();
  // Eigen sorts the singular values in decreasing order: column 2 belongs to the smallest.
  if ((u * v.transpose()).determinant() < 0.0) {
    u.col(2) = -u.col(2);
  }
  return u * v.transpose();
}

int extract_rotation(const Eigen::Matrix3d& a,
                     Eigen::Quaterniond& rotation,
                     int max_iterations,
                     double tolerance) {
  const double norm = a.norm();
  if (!(norm > 0.0) || !std::isfinite(norm)) {
    return 0;
  }
  // Unit Frobenius norm: the iteration is scale-invariant, and the guard below is then a
  // dimensionless 1e-9 as in the paper.
  const Eigen::Matrix3d unit = a / norm;
  constexpr double kDenominatorGuard = 1e-9;
  int iterations = 0;
  while (iterations < max_iterations) {
    const Eigen::Matrix3d r = rotation.toRotationMatrix();
    const Eigen::Vector3d torque =
        r.col(0).cross(unit.col(0)) + r.col(1).cross(unit.col(1)) + r.col(2).cross(unit.col(2));
    const double alignment =
        std::abs(r.col(0).dot(unit.col(0)) + r.col(1).dot(unit.col(1)) + r.col(2).dot(unit.col(2)));
    const Eigen::Vector3d omega = torque / (alignment + kDenominatorGuard);
    const double angle = omega.norm();
    if (angle < tolerance) {
      break;
    }
    ++iterations;
    rotation = Eigen::Quaterniond(Eigen::AngleAxisd(angle, omega / angle)) * rotation;
    rotation.normalize();
  }
  return iterations;
}

}  // namespace softbench::shape_matching
