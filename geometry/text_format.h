// SPDX-License-Identifier: MIT
#pragma once

#include <Eigen/Core>

#include <sstream>
#include <string>

namespace softbench {

// Numbers in messages, formatted one way everywhere. Streams, not string concatenation: GCC 12
// at -O3 warns falsely (-Wrestrict) on "[" + std::string.

/// `value` with `significant_digits` (a stream's default of 6 unless told).
inline std::string format_number(double value, int significant_digits = 6) {
  std::ostringstream out;
  out.precision(significant_digits);
  out << value;
  return out.str();
}

/// "[x, y, z]": the way a scene file writes a vector, so messages echo what a user typed.
inline std::string format_vector(const Eigen::Vector3d& value) {
  std::ostringstream out;
  out << '[' << value.x() << ", " << value.y() << ", " << value.z() << ']';
  return out.str();
}

}  // namespace softbench
