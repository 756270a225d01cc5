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
              "N/m per spring, used only when stiffness_from is \"given\" (the thesis: 180). "
              "Stiffer: smaller deformation and a smaller stable dt for symplectic Euler.")
      .choice("stiffness_from", &Params::stiffness_from,
              {{"given", Params::StiffnessFrom::kGiven},
               {"young_modulus", Params::StiffnessFrom::kYoungModulus}},
              "\"young_modulus\" (default): k_e = E * (volume of the tets sharing e) / L_e^2 "
              "(Van Gelder 1998), following the material and the mesh resolution; \"given\": "
              "every spring has `stiffness` (the thesis).")
      .number("stiffness_scale", &Params::stiffness_scale, Range::positive(),
              "multiplies every spring's stiffness (default 1). Springs from E are not the "
              "material exactly (a spring network has no Poisson's ratio): `softbench "
              "calibrate` fits this so the springs sag and press as the reference does.")
      .number("damping", &Params::damping, Range::non_negative(),
              "N s/m per spring, a dashpot along the spring, the same for every spring (the "
              "thesis: 5; default 0). More: faster settling, less rebound.")
      .number("rayleigh_stiffness", &Params::rayleigh_stiffness, Range::non_negative(),
              "s, Rayleigh stiffness damping: each spring gets a further dashpot "
              "rayleigh_stiffness * k_e along it, damping a mode of angular frequency omega at a "
              "ratio of about rayleigh_stiffness * omega / 2 (faster modes more). Default 0.")
      .number("mass_damping", &Params::mass_damping, Range::non_negative(),
              "1/s, Rayleigh mass damping: a drag -mass_damping * m * v on every vertex, damping "
              "a mode of angular frequency omega at a ratio of mass_damping / (2 omega) (slow "
              "modes more). Default 0.")
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
              "matrix-free preconditioned CG on the springs, warm-started, stopping at "
              "cg_tolerance (fast; as accurate as cg_tolerance asks).")
      .choice("preconditioner", &Params::preconditioner,
              {{"ssor", Params::Preconditioner::kSsor},
               {"block_jacobi", Params::Preconditioner::kBlockJacobi}},
              "\"cg\" only. \"ssor\": symmetric Gauss-Seidel sweeps in Eisenstat's form, "
              "about half the iterations of \"block_jacobi\" (the inverse 3x3 vertex blocks) "
              "at about the same cost per iteration.")
      .number("cg_tolerance", &Params::cg_tolerance, Range{0.0, 1.0, false, false},
              "the estimated energy-norm error of the step's new velocity, relative, at which CG "
              "stops; the default 1e-3 is corotational_fem's, so the two compare at one accuracy. "
              "On the liver scenes (springs from E, calibrated, mass damping 5 /s) it follows "
              "CHOLMOD's tool force within 1e-4 of its peak (RMS 1.3e-5 on the press, 1.4e-6 on "
              "the pull) at 6.7 iterations a step where 1e-6 takes 15.6; with the thesis's stiff, "
              "damped springs 8e-4 off the peak. Each solve ends with an exact correction of the "
              "rigid translations, so a free body keeps its momentum whatever the tolerance. "
              "Smaller: more accurate, more iterations.")
      .integer("cg_max_iterations", &Params::cg_max_iterations, 1, std::numeric_limits<int>::max(),
               "cap on CG iterations per step; a step that hits it reports iterations == cap and "
               "its residual.")
      .record("calibrated", &Params::calibrated,
              "null, or the record `softbench calibrate` writes when it fitted stiffness_scale: "
              "the reference, dt, its sag and press forces, the errors left.");
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
  info.mass_damping = "mass_damping";
  // Van Gelder's springs from E, scaled: a decade and a half either way covers any mesh.
  info.calibration.fitted = {{"stiffness_scale", 0.05, 20.0, true}};
  info.calibration.fixed = {
      {"stiffness_from", "young_modulus"}, {"damping", 0.0}, {"rayleigh_stiffness", 0.0}};
  info.calibration.matched_damping = [](double alpha, double) {
    return nlohmann::json{{"mass_damping", alpha}};
  };
  // Looser CG stops: fewer iterations a step.
  info.speed_settings = {{{"cg_tolerance", 1e-2}}, {{"cg_tolerance", 1e-1}}};
  return info;
}

}  // namespace softbench
