// SPDX-License-Identifier: MIT
// Projective Dynamics' parameter table (declared once: reading, echoing, documenting) and the
// registry entry.
#include "models/projective_dynamics/projective_dynamics.h"
#include "models/projective_dynamics/projective_dynamics_model.h"

namespace softbench {
namespace projective_dynamics {
namespace {

using Params = ProjectiveDynamicsParams;

ParamTable<Params> make_param_table() {
  ParamTable<Params> table;
  table
      .integer("iterations", &Params::iterations, 1, 10000,
               "local/global iterations per step (the speed knob). More: closer to the exact "
               "backward Euler step of the corotated energy, slower (each is a pass over the "
               "tets and three triangular solve pairs on the one factor).")
      .number("tolerance", &Params::tolerance, Range::non_negative(),
              "stop a step early when an iteration moves no vertex by more than tolerance x the "
              "rest bounding-box diagonal; 0: always run `iterations`. A step that ends above it "
              "counts as truncated.")
      .number("rayleigh_mass", &Params::rayleigh_mass, Range::non_negative(),
              "1/s, Rayleigh mass damping alpha: a drag -alpha M v. More: slower, less "
              "oscillating motion.")
      .number("chebyshev_rho", &Params::chebyshev_rho, Range{0.0, 1.0, true, false},
              "Chebyshev acceleration (Wang 2015): the plain iteration's estimated spectral "
              "radius in [0, 1); 0: off. Too large diverges, too small gains little.")
      .integer("chebyshev_delay", &Params::chebyshev_delay, 1, 10000,
               "plain iterations before the Chebyshev acceleration starts.")
      .integer("rotation_iterations", &Params::rotation_iterations, 1, 100,
               "rotation-extraction updates per element per iteration (warm-started from the "
               "last iteration's rotation).");
  return table;
}

}  // namespace

const ParamTable<ProjectiveDynamicsParams>& param_table() {
  static const ParamTable<ProjectiveDynamicsParams> table = make_param_table();
  return table;
}

void validate(const ProjectiveDynamicsParams& params, const std::string& where) {
  // Round trip through the table: its ranges are the single statement of what is valid.
  static_cast<void>(param_table().read(param_table().to_json(params), where, ""));
}

}  // namespace projective_dynamics

ModelInfo projective_dynamics_info() {
  ModelInfo info;
  info.name = "projective_dynamics";
  info.summary =
      "Projective Dynamics (Bouaziz et al. 2014): corotated tets as ARAP + volume constraints, "
      "local rotations and one constant CHOLMOD factor, holds by multipliers on the kept factor";
  info.parameters = projective_dynamics::param_table().docs();
  info.create = [](const TetMesh& mesh, const Material& material, const nlohmann::json& params,
                   const ParamSource& source) -> std::unique_ptr<SoftBody> {
    const ProjectiveDynamicsParams parsed =
        projective_dynamics::param_table().read(params, source.file, source.pointer);
    validate_material(material, source.file + ": /material");
    return std::make_unique<projective_dynamics::ProjectiveDynamicsModel>(mesh, material, parsed);
  };
  info.settling_damping = {{"rayleigh_mass", 2.0}};  // 1/s
  info.mass_damping = "rayleigh_mass";
  info.speed_settings = {{{"iterations", 5}}, {{"iterations", 2}}};
  return info;
}

}  // namespace softbench
