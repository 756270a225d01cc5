// SPDX-License-Identifier: MIT
#include "harness/calibrate/calibration.h"

#include "geometry/input_error.h"
#include "geometry/mesh_io.h"
#include "geometry/mesh_measures.h"
#include "geometry/mesh_validation.h"
#include "harness/run/run_monitor.h"
#include "harness/run/scene_mesh.h"
#include "models/model_registry.h"
#include "scenes/scene_regions.h"

#include <cmath>
#include <iomanip>
#include <iostream>
#include <memory>
#include <sstream>
#include <utility>
#include <vector>

namespace softbench::harness {
namespace {

constexpr const char* kModel = kCalibratedModel;

// The model's settling damping (ModelInfo::settling_damping) where the block sets none or zero.
nlohmann::json with_settling_damping(const std::string& model, nlohmann::json params) {
  if (params.is_null()) {
    params = nlohmann::json::object();
  }
  for (const auto& [key, value] : builtin_models().at(model).settling_damping.items()) {
    if (!params.contains(key) || params[key] == 0.0) {
      params[key] = value;
    }
  }
  return params;
}

}  // namespace

std::string format_cm(double metres) {
  std::ostringstream out;
  out << std::fixed << std::setprecision(3) << 100.0 * metres << " cm";
  return out.str();
}

StaticSag static_sag(const scenes::Scene& scene,
                     const TetMesh& mesh,
                     const std::string& model,
                     const nlohmann::json& params,
                     const StaticSagOptions& options) {
  const std::unique_ptr<SoftBody> body = builtin_models().at(model).create(
      mesh, scene.material, params, {scene.source.string(), "/models/" + model});
  std::vector<PositionConstraint> pins;
  std::vector<char> fixed(static_cast<std::size_t>(mesh.num_vertices()), 0);
  RunMonitor monitor(mesh, scene.limits, bounding_box_diagonal(mesh.rest_positions()));
  for (int vertex : scenes::required_fixed_vertices(
           scene, mesh, "calibrate", "the static sag it fits is the body's, hanging from it")) {
    pins.push_back({vertex, mesh.rest_positions().col(vertex)});
    fixed[static_cast<std::size_t>(vertex)] = 1;
  }
  StepInput input;
  input.gravity = scene.gravity.acceleration;
  input.constraints = pins;
  const Eigen::Vector3d down = input.gravity.normalized();

  StaticSag result;
  const int window = static_cast<int>(std::ceil(1.0 / scene.dt));
  const int max_steps = static_cast<int>(std::ceil(options.max_time / scene.dt));
  int slow_steps = 0;
  for (int step = 0; step < max_steps && !result.settled; ++step) {
    if (!monitor.after_step(step, body->step(scene.dt, input), *body, pins)) {
      result.stable = false;
      return result;
    }
    slow_steps = monitor.free_speed() < options.rest_speed ? slow_steps + 1 : 0;
    result.settled = slow_steps >= window;
    result.time = (step + 1) * scene.dt;
  }
  double sum = 0.0;
  int free_vertices = 0;
  for (int v = 0; v < mesh.num_vertices(); ++v) {
    if (fixed[static_cast<std::size_t>(v)] == 0) {
      sum += (body->positions().col(v) - mesh.rest_positions().col(v)).dot(down);
      ++free_vertices;
    }
  }
  result.sag = free_vertices > 0 ? sum / free_vertices : 0.0;
  return result;
}

StiffnessCalibration calibrate_bullet_softbody(const scenes::Scene& scene,
                                               double tolerance,
                                               std::ostream* progress) {
  builtin_models().at(kModel);  // an InputError naming the known models if Bullet is not built
  const TetMesh mesh = read_scene_mesh(scene).body;  // checked against the scene's units
  StiffnessCalibration result;

  // The reference: the corotational FEM, or until it is registered, springs from E.
  nlohmann::json reference_params;
  if (builtin_models().contains("corotational_fem")) {
    result.against = "corotational_fem";
    reference_params = scene.parameters_for(result.against);
  } else {
    result.against = "mass_spring";
    reference_params = scene.parameters_for(result.against);
    reference_params["stiffness_from"] = "young_modulus";
  }
  const StaticSag reference = static_sag(scene, mesh, result.against,
                                         with_settling_damping(result.against, reference_params));
  if (!reference.stable || !reference.settled || reference.sag <= 0.0) {
    throw InputError(scene.source.string() + ": the reference " + result.against
                     + " did not come to rest under gravity (stable: "
                     + (reference.stable ? "yes" : "no") + "); nothing to calibrate against");
  }
  result.reference_sag = reference.sag;
  if (progress != nullptr) {
    *progress << result.against << ": static sag " << format_cm(reference.sag) << " (at rest after "
              << reference.time << " s)\n";
  }

  nlohmann::json block = scene.parameters_for(kModel);
  block.erase("calibrated");
  const nlohmann::json defaults =
      builtin_models()
          .at(kModel)
          .create(mesh, scene.material, block,
                  {scene.source.string(), "/models/" + std::string(kModel)})
          ->parameters();
  int iterations = defaults["position_iterations"];
  const auto sag_at = [&](double stiffness) {
    nlohmann::json params = block;
    params["stiffness"] = stiffness;
    params["position_iterations"] = iterations;
    const StaticSag sag = static_sag(scene, mesh, kModel, with_settling_damping(kModel, params));
    ++result.evaluations;
    if (progress != nullptr) {
      *progress << kModel << ": stiffness " << stiffness << ", position_iterations " << iterations
                << ": sag " << (sag.stable ? format_cm(sag.sag) : "unstable")
                << (sag.settled ? "" : " (not at rest)") << "\n";
    }
    return sag.stable ? sag.sag : INFINITY;  // unstable counts as too soft
  };
  const auto close_enough = [&](double sag) {
    return std::abs(sag / result.reference_sag - 1.0) <= tolerance;
  };

  // kLST = 1 is the stiffest a link gets; if that is still too soft, more iterations.
  constexpr int kMaxIterations = 1024;
  double stiff = 1.0;
  double stiff_sag = sag_at(stiff);
  while (stiff_sag > result.reference_sag && !close_enough(stiff_sag)) {
    if (2 * iterations > kMaxIterations) {
      throw InputError(scene.source.string() + ": " + kModel + " sags " + format_cm(stiff_sag)
                       + " even at stiffness 1 and " + std::to_string(iterations)
                       + " position iterations, more than " + result.against + "'s "
                       + format_cm(result.reference_sag));
    }
    iterations *= 2;
    stiff_sag = sag_at(stiff);
  }
  double stiffness = stiff;
  double sag = stiff_sag;
  if (!close_enough(sag)) {
    // Bracket: soft (sag above the reference) .. stiff (below), in log kLST.
    constexpr double kMinStiffness = 1e-6;
    double soft = 0.1;
    double soft_sag = sag_at(soft);
    while (soft_sag < result.reference_sag && !close_enough(soft_sag)) {
      if (soft * 0.1 < kMinStiffness) {
        throw InputError(scene.source.string() + ": " + kModel + " sags only " + format_cm(soft_sag)
                         + " at stiffness " + std::to_string(soft) + ", less than " + result.against
                         + "'s " + format_cm(result.reference_sag));
      }
      stiff = soft;
      soft *= 0.1;
      soft_sag = sag_at(soft);
    }
    stiffness = soft;
    sag = soft_sag;
    constexpr int kMaxBisections = 30;
    for (int k = 0; k < kMaxBisections && !close_enough(sag); ++k) {
      stiffness = std::sqrt(soft * stiff);
      sag = sag_at(stiffness);
      (sag > result.reference_sag ? soft : stiff) = stiffness;
    }
  }
  result.sag = sag;

  nlohmann::json fitted = block;
  fitted["stiffness"] = stiffness;
  fitted["position_iterations"] = iterations;
  fitted["calibrated"] = {
      {"against", result.against}, {"dt", scene.dt}, {"sag", result.reference_sag}};
  // The effective block (defaults filled in), as the model echoes it.
  result.params = builtin_models()
                      .at(kModel)
                      .create(mesh, scene.material, fitted, {scene.source.string(), "/models/"})
                      ->parameters();
  return result;
}

}  // namespace softbench::harness
