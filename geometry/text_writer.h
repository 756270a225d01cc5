// SPDX-License-Identifier: MIT
#pragma once

#include <Eigen/Core>

#include <charconv>
#include <ostream>

namespace softbench {

/// Writes `value` with the fewest digits that read back to exactly the same double (at most 17
/// significant digits), so every text writer round-trips without loss.
inline void write_double(std::ostream& out, double value) {
  char buffer[32];
  const auto result = std::to_chars(buffer, buffer + sizeof(buffer), value);
  out.write(buffer, result.ptr - buffer);
}

/// Writes "x y z" (no line break), each coordinate as write_double() does.
inline void write_xyz(std::ostream& out, const Eigen::Ref<const Eigen::Vector3d>& point) {
  write_double(out, point.x());
  out << ' ';
  write_double(out, point.y());
  out << ' ';
  write_double(out, point.z());
}

}  // namespace softbench
