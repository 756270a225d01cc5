// SPDX-License-Identifier: MIT
// The XPBD parameter table (declared once: reading, echoing, documenting) and the registry
// entry.
#include "models/xpbd/xpbd.h"
#include "models/xpbd/xpbd_model.h"

namespace softbench {
namespace xpbd {
namespace {

using Params = XpbdParams;

ParamTable<Params> make_param_table() {
  ParamTable<Params> table;
  table
      .integer("substeps", &Params::substeps, 1, kMaxSubsteps,
               "substeps per step at least (more where stability_ratio asks), one prediction and "
               "`iterations` sweeps each (Macklin et al. "
               "2019's small steps). More: closer to the implicit solution (the resting shape "
               "converges to its energy's equilibrium; 10 is within 0.5% of it on the hanging "
               "liver), stable for stiffer materials; cost proportional. The material does not "
               "change with it.")
      .integer("iterations", &Params::iterations, 1, 100000,
               "Gauss-Seidel sweeps over the tets per substep, lambda accumulated over them. "
               "More: closer to each substep's implicit solution; substeps buy more for the "
               "same work.")
      .number("mass_damping", &Params::mass_damping, Range::non_negative(),
              "1/s, Rayleigh mass damping: a drag -mass_damping m v on every vertex, implicit "
              "per substep. More: slower, less oscillating motion.")
      .number("stability_ratio", &Params::stability_ratio, Range::non_negative(),
              "the largest (h omega)^2 a substep may have, omega the stiffest tet's shear rate "
              "sqrt(mu V sum |grad N|^2 / m): a step takes more than `substeps` where needed. "
              "The sweep integrates shear explicitly and diverges from about 1.6-3.3; 0: no "
              "bound (fast, and unstable for stiff materials or small elements).");
  return table;
}

}  // namespace

const ParamTable<XpbdParams>& param_table() {
  static const ParamTable<XpbdParams> table = make_param_table();
  return table;
}

void validate(const XpbdParams& params, const std::string& where) {
  // Round trip through the table: its ranges are the single statement of what is valid.
  static_cast<void>(param_table().read(param_table().to_json(params), where, ""));
}

}  // namespace xpbd

ModelInfo xpbd_info() {
  ModelInfo info;
  info.name = "xpbd";
  info.summary =
      "XPBD with small steps (Macklin et al. 2016, 2019) on the stable neo-Hookean constraints "
      "of Macklin & Mueller 2021, from the material's E and nu; lumped masses, Gauss-Seidel "
      "sweeps";
  info.parameters = xpbd::param_table().docs();
  info.create = [](const TetMesh& mesh, const Material& material, const nlohmann::json& params,
                   const ParamSource& source) -> std::unique_ptr<SoftBody> {
    const XpbdParams parsed = xpbd::param_table().read(params, source.file, source.pointer);
    validate_material(material, source.file + ": /material");
    return std::make_unique<xpbd::XpbdModel>(mesh, material, parsed);
  };
  // The compliances are material constants: the model follows the material, nothing to fit
  // (calibration stays empty), and the stability map varies Young's modulus (the default axis).
  info.settling_damping = {{"mass_damping", 2.0}};  // 1/s
  info.mass_damping = "mass_damping";
  // Fewer substeps: cheaper steps, a softer-than-the-material static response and less
  // stability margin for stiff materials.
  // At the default stability_ratio the liver at 1/60 s needs 10: cheaper settings give up the
  // margin (5 is at the measured onset for the liver's stiffest tet, 2 past it).
  info.speed_settings = {{{"substeps", 5}, {"stability_ratio", 2.0}},
                         {{"substeps", 2}, {"stability_ratio", 0.0}}};
  return info;
}

}  // namespace softbench
