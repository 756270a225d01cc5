// SPDX-License-Identifier: MIT
// The corotational FEM parameter table (declared once: reading, echoing, documenting) and the
// registry entry.
#include "models/corotational_fem/corotational_fem.h"
#include "models/corotational_fem/corotational_fem_model.h"

#include <limits>

namespace softbench {
namespace corotational_fem {
namespace {

using Params = CorotationalFemParams;

ParamTable<Params> make_param_table() {
  constexpr int kIntMax = std::numeric_limits<int>::max();
  ParamTable<Params> table;
  table
      .choice("formulation", &Params::formulation,
              {{"corotational", Params::Formulation::kCorotational},
               {"linear", Params::Formulation::kLinear}},
              "\"corotational\": element rotations factored out (Mueller & Gross 2004), right "
              "under large rotations; \"linear\": plain linear FEM, cheaper, but a rotated body "
              "feels spurious forces.")
      .choice("rotation", &Params::rotation,
              {{"svd", Params::Rotation::kSvd}, {"quaternion", Params::Rotation::kQuaternion}},
              "corotational only. \"svd\": SVD with Irving et al. 2004's sign fix, exact and "
              "robust, ~0.5 us/element; \"quaternion\": Mueller et al. 2016, warm-started from "
              "the last step, ~0.05 us/element/iteration.")
      .integer("rotation_iterations", &Params::rotation_iterations, 1, 1000,
               "quaternion only: most iterations per element and step. More: closer to the exact "
               "rotation under fast rotation, slower.")
      .number("rotation_tolerance", &Params::rotation_tolerance, Range::positive(),
              "quaternion only, rad: elements stop iterating (in batches of 8) once all their next "
              "updates would be smaller.")
      .number("rayleigh_mass", &Params::rayleigh_mass, Range::non_negative(),
              "1/s, Rayleigh mass damping alpha (C = alpha M + beta K). More: slower, less "
              "oscillating motion.")
      .number("rayleigh_stiffness", &Params::rayleigh_stiffness, Range::non_negative(),
              "s, Rayleigh stiffness damping beta: damps deformation rates. More: quicker "
              "settling and more CG iterations.")
      .choice("solver", &Params::solver,
              {{"cholmod", Params::LinearSolver::kCholmod},
               {"cg", Params::LinearSolver::kConjugateGradient},
               {"cholesky_pcg", Params::LinearSolver::kCholeskyPcg}},
              "\"cholmod\": exact, refactorises every step (slow); \"cg\": warm-started "
              "Jacobi-PCG to cg_tolerance (fastest); \"cholesky_pcg\": PCG preconditioned by a "
              "Cholesky factor reused across steps, refreshed after a slow solve.")
      .choice(
          "preconditioner", &Params::preconditioner,
          {{"ssor", Params::Preconditioner::kSsor}, {"jacobi", Params::Preconditioner::kJacobi}},
          "cg only. \"ssor\": symmetric block Gauss-Seidel, few iterations of about one "
          "product each, on one thread; \"jacobi\": the inverse diagonal, more iterations, "
          "parallel over vertices on large meshes.")
      .integer("coarse_vertices", &Params::coarse_vertices, 0, kIntMax,
               "ssor only: vertices per aggregate of the two-level solve's coarse level (each "
               "aggregate's translations solved exactly); 0: by the mesh's size (aggregates of 64 "
               "from 2048 vertices, else the whole body). Smaller: fewer iterations on large "
               "meshes, a larger coarse system.")
      .choice("sweep_precision", &Params::sweep_precision,
              {{"auto", Params::SweepPrecision::kAuto},
               {"double", Params::SweepPrecision::kDouble},
               {"single", Params::SweepPrecision::kSingle}},
              "ssor only: the matrix the sweeps read. \"single\": a single-precision copy of "
              "its values made each step, half the memory traffic an iteration (the system "
              "solved is the matrix rounded to single precision, a relative change of 6e-8 in "
              "its entries); \"double\": the matrix itself; \"auto\": single from 2048 "
              "vertices, where it was measured faster.")
      .boolean("projected_warm_start", &Params::projected_warm_start,
               "iterative solvers: start from the best combination (energy norm) of the last "
               "four velocity changes (their products in one pass over the matrix a step) instead "
               "of the last one alone.")
      .number("cg_tolerance", &Params::cg_tolerance, Range{0.0, 1.0, false, false},
              "iterative solvers: the estimated energy-norm error of the step's new velocity, "
              "relative, at which they stop. 1e-3 matches CHOLMOD within 0.03% on the liver press "
              "(19 iterations a step); 1e-2 lets a contact's release slip by a step (7% RMS force "
              "error). Smaller: closer to CHOLMOD, more iterations.")
      .integer("cg_max_iterations", &Params::cg_max_iterations, 1, kIntMax,
               "iterative solvers: cap on iterations per step; a step that hits it reports "
               "iterations == cap and its residual.")
      .integer("refresh_iterations", &Params::refresh_iterations, 0, kIntMax,
               "cholesky_pcg: refactorise before the next step when a solve needed more "
               "iterations. Smaller: more factorisations, fewer iterations.");
  return table;
}

}  // namespace

const ParamTable<CorotationalFemParams>& param_table() {
  static const ParamTable<CorotationalFemParams> table = make_param_table();
  return table;
}

void validate(const CorotationalFemParams& params, const std::string& where) {
  // Round trip through the table: its ranges are the single statement of what is valid.
  static_cast<void>(param_table().read(param_table().to_json(params), where, ""));
}

}  // namespace corotational_fem

ModelInfo corotational_fem_info() {
  ModelInfo info;
  info.name = "corotational_fem";
  info.summary =
      "corotational (warped-stiffness) or linear tetrahedral FEM, lumped masses, Rayleigh "
      "damping, linearised backward Euler with CHOLMOD, Jacobi-PCG or Cholesky-preconditioned CG";
  info.parameters = corotational_fem::param_table().docs();
  info.create = [](const TetMesh& mesh, const Material& material, const nlohmann::json& params,
                   const ParamSource& source) -> std::unique_ptr<SoftBody> {
    const CorotationalFemParams parsed =
        corotational_fem::param_table().read(params, source.file, source.pointer);
    validate_material(material, source.file + ": /material");
    return std::make_unique<corotational_fem::CorotationalFemModel>(mesh, material, parsed);
  };
  info.settling_damping = {{"rayleigh_mass", 2.0}};  // 1/s
  info.mass_damping = "rayleigh_mass";
  // Looser CG stops: fewer iterations a step, and the contact's release slips by a step sooner.
  info.speed_settings = {{{"cg_tolerance", 1e-2}}, {{"cg_tolerance", 1e-1}}};
  return info;
}

}  // namespace softbench
