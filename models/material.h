// SPDX-License-Identifier: MIT
#pragma once

#include <string_view>

namespace softbench {

/// An isotropic elastic material in SI units, as a scene states it.
struct Material {
  double young_modulus = 3000.0;  ///< Pa (the thesis's liver; real liver tissue ~5 kPa)
  double poisson_ratio = 0.3;     ///< dimensionless, in [0, 0.5); near 0.5: nearly incompressible
  double density = 1060.0;        ///< kg/m^3 (soft tissue)
};

/// Lamé's first parameter lambda and the shear modulus mu, Pa.
struct LameParameters {
  double lambda = 0.0;
  double mu = 0.0;
};

/// Throws InputError naming `where` (e.g. "scenes/liver.json: /material") when a value is not
/// finite or out of range: Young's modulus and density must be > 0, Poisson's ratio in [0, 0.5)
/// (0.5 makes lambda infinite).
void validate_material(const Material& material, std::string_view where);

/// lambda = E nu / ((1 + nu)(1 - 2 nu)), mu = E / (2 (1 + nu)).
LameParameters lame_parameters(const Material& material);

}  // namespace softbench
