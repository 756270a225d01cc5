// SPDX-License-Identifier: MIT
#pragma once

#include <Eigen/Core>

#include <sstream>
#include <string>
#include <string_view>

namespace softbench {

// Numbers and text in messages, formatted one way everywhere. Streams, not string concatenation:
// GCC 12 at -O3 warns falsely (-Wrestrict) on "[" + std::string.

/// `value` with `significant_digits` (a stream's default of 6 unless told).
inline std::string format_number(double value, int significant_digits = 6) {
  std::ostringstream out;
  out.precision(significant_digits);
  out << value;
  return out.str();
}

/// `text` fit for a one-line message: its control characters (a line break in a JSON key or a
/// path) written as JSON escapes them ("\n", "\u001b"), everything else as it is.
inline std::string one_line(std::string_view text) {
  std::string shown;
  shown.reserve(text.size());
  for (const char c : text) {
    const auto byte = static_cast<unsigned char>(c);
    if (byte >= 0x20 && byte != 0x7f) {
      shown += c;
      continue;
    }
    switch (c) {
      case '\n':
        shown += "\\n";
        break;
      case '\r':
        shown += "\\r";
        break;
      case '\t':
        shown += "\\t";
        break;
      default: {
        constexpr char kHex[] = "0123456789abcdef";
        shown += "\\u00";
        shown += kHex[byte >> 4];
        shown += kHex[byte & 0xf];
      }
    }
  }
  return shown;
}

/// "[x, y, z]": the way a scene file writes a vector, so messages echo what a user typed.
inline std::string format_vector(const Eigen::Vector3d& value) {
  std::ostringstream out;
  out << '[' << value.x() << ", " << value.y() << ", " << value.z() << ']';
  return out.str();
}

}  // namespace softbench
