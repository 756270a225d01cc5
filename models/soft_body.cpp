// SPDX-License-Identifier: MIT
#include "models/soft_body.h"

namespace softbench {

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
