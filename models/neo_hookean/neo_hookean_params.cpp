// SPDX-License-Identifier: MIT
// The neo-Hookean reference's parameter table (declared once: reading, echoing, documenting) and
// the registry entry.
#include "models/neo_hookean/neo_hookean.h"
#include "models/neo_hookean/neo_hookean_model.h"

#include <limits>

namespace softbench {
namespace neo_hookean {
namespace {

using Params = NeoHookeanParams;

ParamTable<Params> make_param_table() {
  constexpr int kIntMax = std::numeric_limits<int>::max();
  ParamTable<Params> table;
  table
      .choice(
          "projection", &Params::projection,
          {{"always", Params::Projection::kAlways}, {"fallback", Params::Projection::kFallback}},
          "definiteness fix: \"always\": every element's Hessian projected to PSD (clamped "
          "eigenvalues) in every Newton iteration; \"fallback\": the exact Hessian while the "
          "system is positive definite, the projected one once CHOLMOD finds it is not "
          "(fewer iterations).")
      .number("tolerance", &Params::tolerance, Range{0.0, 1.0, false, false},
              "Newton stops when its step's largest vertex displacement is below tolerance x the "
              "rest bounding-box diagonal. Smaller: closer to the exact backward Euler step, more "
              "iterations (each a CHOLMOD factorisation).")
      .integer("max_iterations", &Params::max_iterations, 1, kIntMax,
               "most Newton iterations per step; a step that needs more is reported (residual > "
               "tolerance), not hidden.")
      .number("armijo", &Params::armijo, Range{0.0, 0.5, false, false},
              "line search: a step length s is accepted when the incremental potential drops by "
              "at least armijo x s x its directional derivative. Larger: stricter.")
      .number("backtrack", &Params::backtrack, Range{0.0, 1.0, false, false},
              "line search: a rejected step length is multiplied by this.")
      .integer("max_backtracks", &Params::max_backtracks, 0, 200,
               "line search: most step-length reductions per Newton iteration; then the step is "
               "reported as not converged.")
      .number("rayleigh_mass", &Params::rayleigh_mass, Range::non_negative(),
              "1/s, Rayleigh mass damping alpha: a drag -alpha M v. More: slower, less "
              "oscillating motion.");
  return table;
}

}  // namespace

const ParamTable<NeoHookeanParams>& param_table() {
  static const ParamTable<NeoHookeanParams> table = make_param_table();
  return table;
}

void validate(const NeoHookeanParams& params, const std::string& where) {
  // Round trip through the table: its ranges are the single statement of what is valid.
  static_cast<void>(param_table().read(param_table().to_json(params), where, ""));
}

}  // namespace neo_hookean

ModelInfo neo_hookean_info() {
  ModelInfo info;
  info.name = "neo_hookean";
  info.summary =
      "converged reference (slow): stable neo-Hookean tetrahedral FEM, backward Euler solved to "
      "convergence by Newton with line search and per-element eigenvalue projection, CHOLMOD";
  info.parameters = neo_hookean::param_table().docs();
  info.reference = true;
  info.create = [](const TetMesh& mesh, const Material& material, const nlohmann::json& params,
                   const ParamSource& source) -> std::unique_ptr<SoftBody> {
    const NeoHookeanParams parsed =
        neo_hookean::param_table().read(params, source.file, source.pointer);
    validate_material(material, source.file + ": /material");
    return std::make_unique<neo_hookean::NeoHookeanModel>(mesh, material, parsed);
  };
  info.settling_damping = {{"rayleigh_mass", 2.0}};  // 1/s
  info.mass_damping = "rayleigh_mass";
  return info;
}

}  // namespace softbench
