// SPDX-License-Identifier: MIT
// Vectors between Eigen and Bullet (built with BT_USE_DOUBLE_PRECISION: no rounding either way).
#pragma once

#include <Eigen/Core>
#include <LinearMath/btVector3.h>

namespace softbench::bullet {

inline btVector3 to_bullet(const Eigen::Vector3d& v) {
  return btVector3(v.x(), v.y(), v.z());
}

inline Eigen::Vector3d to_eigen(const btVector3& v) {
  return Eigen::Vector3d(v.x(), v.y(), v.z());
}

}  // namespace softbench::bullet
