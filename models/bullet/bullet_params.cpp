// SPDX-License-Identifier: MIT
// The two Bullet models' parameter tables (declared once: reading, echoing, documenting), their
// registry entries and make functions.
#include "models/bullet/bullet_body.h"
#include "models/bullet/bullet_soft_body.h"
#include "models/json_reader.h"
#include "models/param_table.h"

#include <cmath>
#include <limits>
#include <string>
#include <utility>

namespace softbench {
namespace bullet {
namespace {

constexpr int kMaxCount = std::numeric_limits<int>::max();

ParamTable<BulletSoftBodyParams> make_softbody_table() {
  using Params = BulletSoftBodyParams;
  ParamTable<Params> table;
  table
      .number("stiffness", &Params::stiffness, Range{0.0, 1.0, false, true},
              "Bullet's link stiffness kLST in (0, 1], no unit: its effect depends on dt, "
              "position_iterations and the mesh. Fit it with `softbench calibrate`.")
      .integer("position_iterations", &Params::position_iterations, 1, kMaxCount,
               "Bullet's piterations: link projections per step. More: stiffer, costlier "
               "(linear).")
      .number("damping", &Params::damping, Range::closed(0.0, 1.0),
              "Bullet's kDP in [0, 1]: fraction of each velocity removed per step (depends on "
              "dt). More: faster settling.")
      .number("pose_matching", &Params::pose_matching, Range::closed(0.0, 1.0),
              "Bullet's kMT in [0, 1]: pull toward the rest shape's best rigid placement per "
              "step (per cluster when clusters > 0). Resists large deformation.")
      .number("volume_conservation", &Params::volume_conservation, Range::non_negative(),
              "Bullet's kVC >= 0: pressure keeping the closed surface's volume; 0 = off.")
      .integer("clusters", &Params::clusters, 0, kMaxCount,
               "k-means clusters, each matching its own rigid frame with pose_matching; 0 = "
               "none. More: stiffer locally, costlier.")
      .record("calibrated", &Params::calibrated,
              "null, or the record `softbench calibrate` writes: the reference, dt, its sag and "
              "press forces, the errors left. Echoed so reports show the stiffness was fitted, "
              "and for which dt.");
  return table;
}

ParamTable<BulletDeformableParams> make_deformable_table() {
  using Params = BulletDeformableParams;
  ParamTable<Params> table;
  table
      .choice("force", &Params::force,
              {{"neo_hookean", Params::Force::kNeoHookean},
               {"corotated", Params::Force::kCorotated},
               {"mass_spring", Params::Force::kMassSpring}},
              "Bullet's elastic force: \"neo_hookean\" (stable neo-Hookean from E, nu), "
              "\"corotated\" (E, nu; explicit only in Bullet 3.24: set implicit false and a small "
              "dt), \"mass_spring\" (spring_stiffness per edge).")
      .choice(
          "lame_mapping", &Params::lame_mapping,
          {{"matched", Params::LameMapping::kMatched}, {"direct", Params::LameMapping::kDirect}},
          "neo_hookean only. \"matched\": mu' = 4/3 mu, lambda' = lambda + 5/6 mu (Smith et "
          "al. 2018): small strains follow the scene's E, nu; \"direct\": mu, lambda as "
          "given (Bullet's demos), ~27% softer at nu 0.3.")
      .boolean("implicit", &Params::implicit,
               "true: backward Euler (stable at large dt, costs CG solves); false: symplectic "
               "Euler, stable only below the CFL limit (~1 ms on the liver).")
      .number("damping", &Params::damping, Range::non_negative(),
              "s, neo_hookean only: damping stress d mu (dF + dF^T) + d lambda tr(dF) I. More: "
              "faster settling, more CG iterations.")
      .number("spring_stiffness", &Params::spring_stiffness, Range::non_negative(),
              "N/m per edge, mass_spring only; 0 = young_modulus x mean edge length (k ~ E h).")
      .number("spring_damping", &Params::spring_damping, Range::non_negative(),
              "N s/m per edge, mass_spring only: dashpot along the edge.")
      .number("cg_tolerance", &Params::cg_tolerance, Range{0.0, 1.0, false, false},
              "Bullet's CG stops at r.z < cg_tolerance min(1, b.z0) (~ relative residual "
              "squared). Bullet's double-build default, 2.2e-16, always runs to the cap.")
      .integer("cg_max_iterations", &Params::cg_max_iterations, 1, kMaxCount,
               "CG iterations per solve (Bullet: 300). Hitting it shows as iterations == cap x "
               "linear_solves.")
      .integer("newton_iterations", &Params::newton_iterations, 1, 100,
               "implicit only: linearised solves per step (Bullet: 1). More: closer to the "
               "nonlinear backward Euler step, one CG solve each.")
      .boolean("line_search", &Params::line_search,
               "implicit only: Bullet's backtracking line search. More robust at large dt, "
               "costlier.");
  return table;
}

const ParamTable<BulletSoftBodyParams>& softbody_table() {
  static const ParamTable<BulletSoftBodyParams> table = make_softbody_table();
  return table;
}

const ParamTable<BulletDeformableParams>& deformable_table() {
  static const ParamTable<BulletDeformableParams> table = make_deformable_table();
  return table;
}

std::unique_ptr<SoftBody> make_softbody_body(const TetMesh& mesh,
                                             const Material& material,
                                             const BulletSoftBodyParams& params) {
  return std::make_unique<BulletBody>(
      "bullet_softbody", softbody_table().to_json(params), BulletMesh::from(mesh, material.density),
      [params](const BulletMesh& loaded) { return make_softbody_world(loaded, params); });
}

std::unique_ptr<SoftBody> make_deformable_body(const TetMesh& mesh,
                                               const Material& material,
                                               const BulletDeformableParams& params) {
  return std::make_unique<BulletBody>("bullet_deformable", deformable_table().to_json(params),
                                      BulletMesh::from(mesh, material.density),
                                      [material, params](const BulletMesh& loaded) {
                                        return make_deformable_world(loaded, material, params);
                                      });
}

}  // namespace
}  // namespace bullet

ModelInfo bullet_softbody_info() {
  ModelInfo info;
  info.name = "bullet_softbody";
  info.summary =
      "Bullet 3.24 btSoftBody: position-based links on the edges (kLST, no unit: calibrate "
      "it), optional pose matching, volume conservation and clusters";
  info.parameters = bullet::softbody_table().docs();
  info.create = [](const TetMesh& mesh, const Material& material, const nlohmann::json& params,
                   const ParamSource& source) -> std::unique_ptr<SoftBody> {
    const BulletSoftBodyParams parsed = bullet::softbody_table().read(params, source.file, source.pointer);
    validate_material(material, source.file + ": /material");
    return bullet::make_softbody_body(mesh, material, parsed);
  };
  info.stiffness_axis = {
      "stiffness", false, nlohmann::json::object(),
      "kLST (link stiffness, no unit); btSoftBody's links ignore Young's modulus"};
  // kDP scales velocities, which are zero at rest: the equilibrium does not depend on it.
  info.settling_damping = {{"damping", 0.05}};  // per step
  // kLST over four decades (1 is the stiffest a link gets), at the scene's position_iterations.
  info.calibration.fitted = {{"stiffness", 1e-4, 1.0, true}};
  // kDP removes a fraction of the velocity per step: exp(-alpha dt) is what a drag alpha leaves.
  info.calibration.matched_damping = [](double alpha, double dt) {
    return nlohmann::json{{"damping", 1.0 - std::exp(-alpha * dt)}};
  };
  // Fewer link projections: cheaper (linearly), softer, so refitted stiffer.
  info.speed_settings = {{{"position_iterations", 4}}, {{"position_iterations", 2}}};
  return info;
}

ModelInfo bullet_deformable_info() {
  ModelInfo info;
  info.name = "bullet_deformable";
  info.summary =
      "Bullet 3.24 deformable world: stable neo-Hookean, corotated or mass-spring force from "
      "the material; backward Euler with Bullet's CG, or symplectic Euler";
  info.parameters = bullet::deformable_table().docs();
  info.create = [](const TetMesh& mesh, const Material& material, const nlohmann::json& params,
                   const ParamSource& source) -> std::unique_ptr<SoftBody> {
    const BulletDeformableParams parsed =
        bullet::deformable_table().read(params, source.file, source.pointer);
    validate_material(material, source.file + ": /material");
    return bullet::make_deformable_body(mesh, material, parsed);
  };
  // The neo-Hookean damping stress acts on the velocity gradient, which is zero at rest: the
  // equilibrium does not depend on it. (It is not rotation-invariant: it also brakes a rigid
  // rotation, which is why a free spin turns it off.)
  info.settling_damping = {{"damping", 0.05}};  // s, Bullet's default
  return info;
}

std::unique_ptr<SoftBody> make_bullet_softbody(const TetMesh& mesh,
                                               const Material& material,
                                               const BulletSoftBodyParams& params) {
  validate_material(material, "make_bullet_softbody: material");
  // Round trip through the table: its ranges are the one statement of what is valid.
  static_cast<void>(bullet::softbody_table().read(bullet::softbody_table().to_json(params),
                                                  "make_bullet_softbody", ""));
  return bullet::make_softbody_body(mesh, material, params);
}

std::unique_ptr<SoftBody> make_bullet_deformable(const TetMesh& mesh,
                                                 const Material& material,
                                                 const BulletDeformableParams& params) {
  validate_material(material, "make_bullet_deformable: material");
  static_cast<void>(bullet::deformable_table().read(bullet::deformable_table().to_json(params),
                                                    "make_bullet_deformable", ""));
  return bullet::make_deformable_body(mesh, material, params);
}

}  // namespace softbench
