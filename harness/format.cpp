// SPDX-License-Identifier: MIT
#include "harness/format.h"

#include <cctype>
#include <cmath>
#include <iomanip>
#include <sstream>

namespace softbench::harness {

std::string fixed(double value, int digits) {
  std::ostringstream out;
  out << std::fixed << std::setprecision(digits) << value;
  return out.str();
}

nlohmann::json number_or_null(double value) {
  return std::isfinite(value) ? nlohmann::json(value) : nlohmann::json(nullptr);
}

std::string folder_name(const std::string& name) {
  constexpr std::size_t kMaxLength = 100;  // well inside a file system's 255-byte name limit
  std::string folder = name.substr(0, kMaxLength);
  for (char& c : folder) {
    const bool safe = std::isalnum(static_cast<unsigned char>(c)) != 0 || c == '_' || c == '-'
                      || c == '.';
    if (!safe) {
      c = '_';
    }
  }
  // A leading dot would make "." or ".." (or a hidden folder).
  for (std::size_t i = 0; i < folder.size() && folder[i] == '.'; ++i) {
    folder[i] = '_';
  }
  return folder.empty() ? std::string("_") : folder;
}

std::string percent(double fraction) {
  std::ostringstream out;
  out << std::setprecision(3) << 100.0 * fraction << "%";
  return out.str();
}

}  // namespace softbench::harness
