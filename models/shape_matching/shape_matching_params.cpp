// SPDX-License-Identifier: MIT
// The shape-matching parameter table (declared once: reading, echoing, documenting) and the
// registry entry.
#include "models/shape_matching/shape_matching.h"
#include "models/shape_matching/shape_matching_model.h"

#include <limits>

namespace softbench {
namespace shape_matching {
namespace {

using Params = ShapeMatchingParams;

ParamTable<Params> make_param_table() {
  constexpr int kMaxInt = std::numeric_limits<int>::max();
  ParamTable<Params> table;
  table
      .choice("type", &Params::type,
              {{"linear", Params::Type::kLinear}, {"quadratic", Params::Type::kQuadratic}},
              "\"linear\": goals from a 3x3 map (shear, stretch); \"quadratic\": from a 3x9 map "
              "(also twist and bend; the thesis's choice), about twice the cost per particle.")
      .integer("clusters", &Params::clusters, 1, kMaxInt,
               "number of overlapping clusters, clamped to the particle count (the thesis: 50); "
               "1 = one global cluster. More: more local, larger deformation, more cost.")
      .number("cluster_radius", &Params::cluster_radius, Range::non_negative(),
              "m, region radius around each cluster's seed (farthest-point sampling); 0 = "
              "chosen so that about particles_per_cluster particles take part per cluster.")
      .integer("particles_per_cluster", &Params::particles_per_cluster, 4, kMaxInt,
               "target average cluster size when cluster_radius is 0 (the thesis: 96). More: "
               "stiffer, smoother, more overlap; the cost grows in proportion.")
      .number("alpha", &Params::alpha, Range{0.0, 1.0, false, true},
              "fraction of the way to the goal per step, in (0, 1] (the thesis: 0.72): the "
              "stiffness (with dt). 1: rigid; smaller: softer. Stable at any dt. The material's "
              "Young's modulus and Poisson's ratio are not used (only its density, for masses).")
      .number("beta", &Params::beta, Range::closed(0.0, 1.0),
              "blend of the best linear/quadratic map with the rotation, in [0, 1] (the thesis: "
              "0.63). 0: rigid goals; larger: keeps more deformation, recovers more slowly.")
      .choice("rotation", &Params::rotation,
              {{"svd", Params::Rotation::kSvd}, {"quaternion", Params::Rotation::kQuaternion}},
              "rotation extraction: \"svd\": exact polar rotation by a 3x3 SVD; \"quaternion\": "
              "Mueller et al. 2016's iteration warm-started from the last step (cheaper; lags a "
              "fast spin slightly with few iterations).")
      .integer("rotation_iterations", &Params::rotation_iterations, 1, 1000,
               "most quaternion iterations per cluster and step (stops early below 1e-12 rad). "
               "More: closer to the exact rotation, dearer.")
      .boolean("preserve_volume", &Params::preserve_volume,
               "divide the linear part A of each cluster's fit by cbrt(det A) (a cluster "
               "squashed below 5% of its volume follows its rotation alone), linear and "
               "quadratic goals; false: the fits' own volume change (Mueller 2005's quadratic).")
      .integer("iterations", &Params::iterations, 1, 1000,
               "match-and-pull passes per step, each from where the last left the particles, "
               "as position-based engines iterate (1: the thesis's single pull). More: a "
               "stiffer body at the same alpha, each pass costing about one single-pass step.")
      .record("calibrated", &Params::calibrated,
              "null, or the record `softbench calibrate` writes when it fitted alpha and beta: "
              "the reference, dt, its sag and press forces, the errors left.");
  return table;
}

}  // namespace

const ParamTable<ShapeMatchingParams>& param_table() {
  static const ParamTable<ShapeMatchingParams> table = make_param_table();
  return table;
}

void validate(const ShapeMatchingParams& params, const std::string& where) {
  // Round trip through the table: its ranges are the single statement of what is valid (a NaN
  // becomes JSON null and is rejected as "expected a number ..., got null").
  static_cast<void>(param_table().read(param_table().to_json(params), where, ""));
}

}  // namespace shape_matching

ModelInfo shape_matching_info() {
  ModelInfo info;
  info.name = "shape_matching";
  info.summary =
      "meshless shape matching (Mueller et al. 2005): linear or quadratic goals, overlapping "
      "clusters, alpha pull; unconditionally stable; ignores E and nu (density only)";
  info.parameters = shape_matching::param_table().docs();
  info.create = [](const TetMesh& mesh, const Material& material, const nlohmann::json& params,
                   const ParamSource& source) -> std::unique_ptr<SoftBody> {
    const ShapeMatchingParams parsed =
        shape_matching::param_table().read(params, source.file, source.pointer);
    validate_material(material, source.file + ": /material");
    return std::make_unique<shape_matching::ShapeMatchingModel>(mesh, material, parsed);
  };
  info.stiffness_axis = {"alpha", false, nlohmann::json::object(),
                         "alpha (pull toward the goal per step); shape matching ignores Young's "
                         "modulus"};
  // Both knobs of its stiffness: alpha (the pull per step, down to very soft) and beta (how
  // much deformation the goals keep), beta up to 0.9 only. Near 1 the quadratic goals keep
  // almost any fold, and the edge where the liver crumples is sharp and load-dependent: at
  // alpha 0.98 the fit's sag pulled beta to 0.968, which settles and presses as a tissue, and
  // the same block on liver_pull's grasp crumples (224% volume change, 659 tets inverted),
  // where beta 0.9 (and 0.8, and the thesis's 0.63) recovers below 1%.
  info.calibration.fitted = {{"alpha", 0.01, 1.0, true}, {"beta", 0.0, 0.9, false}};
  // Fewer, larger clusters: fewer polar decompositions, a stiffer and less local response;
  // fewer passes: half the cost, a body whose weight crosses fewer clusters a step.
  info.speed_settings = {{{"clusters", 20}}, {{"iterations", 2}}};
  return info;
}

}  // namespace softbench
