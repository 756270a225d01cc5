// SPDX-License-Identifier: MIT
#include "harness/format.h"

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

}  // namespace softbench::harness
