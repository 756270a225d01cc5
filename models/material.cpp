// SPDX-License-Identifier: MIT
#include "models/material.h"

#include "geometry/input_error.h"

#include <cmath>
#include <sstream>
#include <string>

namespace softbench {
namespace {

[[noreturn]] void reject(std::string_view where,
                         std::string_view key,
                         std::string_view expected,
                         double got) {
  std::ostringstream message;
  message << where << "/" << key << ": expected " << expected << ", got " << got;
  throw InputError(message.str());
}

}  // namespace

void validate_material(const Material& material, std::string_view where) {
  if (!std::isfinite(material.young_modulus) || material.young_modulus <= 0.0) {
    reject(where, "young_modulus", "a positive number (Pa)", material.young_modulus);
  }
  if (!std::isfinite(material.poisson_ratio) || material.poisson_ratio < 0.0
      || material.poisson_ratio >= 0.5) {
    reject(where, "poisson_ratio", "a number in [0, 0.5)", material.poisson_ratio);
  }
  if (!std::isfinite(material.density) || material.density <= 0.0) {
    reject(where, "density", "a positive number (kg/m^3)", material.density);
  }
}

LameParameters lame_parameters(const Material& material) {
  const double e = material.young_modulus;
  const double nu = material.poisson_ratio;
  return {e * nu / ((1.0 + nu) * (1.0 - 2.0 * nu)), e / (2.0 * (1.0 + nu))};
}

}  // namespace softbench
