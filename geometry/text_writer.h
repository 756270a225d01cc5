// SPDX-License-Identifier: MIT
#pragma once

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

}  // namespace softbench
