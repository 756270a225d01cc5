// SPDX-License-Identifier: MIT
#include "models/soft_body.h"

#include <stdexcept>
#include <string>

namespace softbench {

void SoftBody::check_velocities(const Eigen::Matrix3Xd& velocities) const {
  if (velocities.cols() != positions().cols()) {
    throw std::invalid_argument(std::string(name()) + ": set_velocities: expected 3 x "
                                + std::to_string(positions().cols()) + " velocities, got 3 x "
                                + std::to_string(velocities.cols()));
  }
  if (!velocities.allFinite()) {
    throw std::invalid_argument(std::string(name()) + ": set_velocities: a NaN or Inf velocity");
  }
}

Eigen::Matrix3Xd SoftBody::constraint_forces() const {
  return Eigen::Matrix3Xd::Zero(3, positions().cols());
}

double SoftBody::elastic_energy() const {
  return std::numeric_limits<double>::quiet_NaN();
}

std::size_t SoftBody::memory_bytes() const {
  return 0;
}

}  // namespace softbench
