// SPDX-License-Identifier: MIT
// The mass-spring parameter table (declared once: reading, echoing, documenting) and the
// registry entry.
#include "models/mass_spring/mass_spring.h"
#include "models/mass_spring/mass_spring_model.h"

#include <limits>

namespace softbench {
namespace mass_spring {
namespace {

using Params = MassSpringParams;

ParamTable<Params> make_param_table() {
  ParamTable<Params> table;
  table
      .number("stiffness", &Params::stiffness, Range::positive(),
              "N/m per spring, used when stiffness_from is \"given\" (the thesis: 180). Stiffer: "
              "smaller deformation and a smaller stable dt for symplectic Euler.")
      .choice("stiffness_from", &Params::stiffness_from,
              {{"given", Params::StiffnessFrom::kGiven},
               {"young_modulus", Params::StiffnessFrom::kYoungModulus}},
              "\"given\": every spring has `stiffness`; \"young_modulus\": k_e = E * (volume of "
              "the tets sharing e) / L_e^2 (Van Gelder 1998), following material and resolution.")
      .number("damping", &Params::damping, Range::non_negative(),
              "N s/m per spring, along the spring (the thesis: 5). More: faster settling, less "
              "rebound.")
      .number("mass_damping", &Params::mass_damping, Range::non_negative(),
              "1/s, a drag -mass_damping * m * v on every vertex.")
      .choice("integrator", &Params::integrator,
              {{"symplectic_euler", Params::Integrator::kSymplecticEuler},
               {"implicit_euler", Params::Integrator::kImplicitEuler}},
              "\"symplectic_euler\": cheap, stable only for dt below ~2/omega_max; "
              "\"implicit_euler\" (Baraff & Witkin 1998): stable at any dt, damps high "
              "frequencies numerically.")
      .choice("solver", &Params::solver,
              {{"cholmod", Params::LinearSolver::kCholmod},
               {"cg", Params::LinearSolver::kConjugateGradient}},
              "implicit Euler only. \"cholmod\": exact, refactorises every step; \"cg\": "
              "warm-started Jacobi-PCG, stops at cg_tolerance (fast, approximate).")
      .number("cg_tolerance", &Params::cg_tolerance, Range{0.0, 1.0, false, false},
              "the estimated energy-norm error of the step's new velocity, relative, at which CG "
              "stops. 1e-6 matches CHOLMOD within 4e-6 of the peak force on the liver press; 1e-3 "
              "does not (a 6% peak error: the thesis's stiff, damped springs make the contact "
              "forces sensitive). Smaller: more accurate, more iterations.")
      .integer("cg_max_iterations", &Params::cg_max_iterations, 1, std::numeric_limits<int>::max(),
               "cap on CG iterations per step; a step that hits it reports iterations == cap and "
               "its residual.");
  return table;
}

}  // namespace

const ParamTable<MassSpringParams>& param_table() {
  static const ParamTable<MassSpringParams> table = make_param_table();
  return table;
}

void validate(const MassSpringParams& params, const std::string& where) {
  // Round trip through the table: its ranges are the single statement of what is valid (a NaN
  // becomes JSON null and is rejected as "expected a number ..., got null").
  static_cast<void>(param_table().read(param_table().to_json(params), where, ""));
}

}  // namespace mass_spring

ModelInfo mass_spring_info() {
  ModelInfo info;
  info.name = "mass_spring";
  info.summary =
      "springs on the tet edges, lumped masses; symplectic Euler or implicit Euler (Baraff & "
      "Witkin 1998) with CHOLMOD or CG";
  info.parameters = mass_spring::param_table().docs();
  info.create = [](const TetMesh& mesh, const Material& material, const nlohmann::json& params,
                   const ParamSource& source) -> std::unique_ptr<SoftBody> {
    const MassSpringParams parsed =
        mass_spring::param_table().read(params, source.file, source.pointer);
    validate_material(material, source.file + ": /material");
    return std::make_unique<mass_spring::MassSpringModel>(mesh, material, parsed);
  };
  info.settling_damping = {{"mass_damping", 2.0}};  // 1/s
  info.stiffness_axis.fixed_params = {{"stiffness_from", "young_modulus"}};
  info.stiffness_axis.note =
      "the material's Young's modulus, springs derived from it (stiffness_from = young_modulus)";
  return info;
}

}  // namespace softbench
