// SPDX-License-Identifier: MIT
#include "models/soft_body.h"

#include <stdexcept>
#include <string>

namespace softbench {

void SoftBody::check_field(const char* setter,
                           const char* what,
                           const Eigen::Matrix3Xd& field) const {
  if (field.cols() != positions().cols()) {
    throw std::invalid_argument(std::string(name()) + ": " + setter + ": expected 3 x "
                                + std::to_string(positions().cols()) + " " + what + ", got 3 x "
                                + std::to_string(field.cols()));
  }
  if (!field.allFinite()) {
    throw std::invalid_argument(std::string(name()) + ": " + setter + ": a NaN or Inf in the "
                                + what);
  }
}

void SoftBody::check_velocities(const Eigen::Matrix3Xd& velocities) const {
  check_field("set_velocities", "velocities", velocities);
}

void SoftBody::check_state(const Eigen::Matrix3Xd& positions,
                           const Eigen::Matrix3Xd& velocities) const {
  check_field("set_state", "positions", positions);
  check_field("set_state", "velocities", velocities);
}

double SoftBody::elastic_energy() const {
  return std::numeric_limits<double>::quiet_NaN();
}

std::size_t SoftBody::memory_bytes() const {
  return 0;
}

}  // namespace softbench
