// SPDX-License-Identifier: MIT
#include "harness/calibrate/tissue_response.h"

#include "harness/format.h"
#include "geometry/input_error.h"
#include "geometry/mesh_measures.h"
#include "geometry/mesh_topology.h"
#include "harness/run/metrics.h"
#include "harness/run/plausibility.h"
#include "harness/run/run_monitor.h"
#include "harness/run/scene_stepper.h"
#include "models/model_registry.h"
#include "scenes/scene_regions.h"

#include <Eigen/Geometry>

#include <chrono>
#include <cmath>
#include <limits>
#include <memory>
#include <sstream>

namespace softbench::harness {
namespace {


std::unique_ptr<SoftBody> create(const scenes::Scene& scene,
                                 const TetMesh& mesh,
                                 const std::string& model,
                                 const nlohmann::json& params) {
  return builtin_models().at(model).create(mesh, scene.material, params,
                                           {scene.source.string(), "/models/" + model});
}

/// The scene's instrument pressing straight down along gravity on `target` (the settled press
/// vertex): a scene of its own, with only the fixed region, supports and gravity kept.
scenes::Scene press_scene(const scenes::Scene& scene,
                          const SceneMesh& mesh,
                          const Eigen::Vector3d& target,
                          const PressSettings& settings) {
  scenes::Scene press = scene;
  press.gravity.off_at = scenes::kNever;
  press.grasp.reset();
  press.initial_velocity.reset();
  press.requirements.reset();
  scenes::Instrument& tool = *press.instrument;
  tool.grasp.reset();
  tool.start = 0.0;
  tool.release = scenes::kNever;
  const Eigen::Vector3d down = scene.gravity.acceleration.normalized();
  const Eigen::Quaterniond turn = Eigen::Quaterniond::FromTwoVectors(-Eigen::Vector3d::UnitZ(), down);
  // The tip: the tool's vertex furthest along gravity once turned.
  Eigen::Vector3d tip = Eigen::Vector3d::Zero();
  double lowest = -std::numeric_limits<double>::infinity();
  for (int v = 0; v < mesh.instrument->num_vertices(); ++v) {
    const Eigen::Vector3d turned = turn * mesh.instrument->vertices.col(v);
    if (turned.dot(down) > lowest) {
      lowest = turned.dot(down);
      tip = turned;
    }
  }
  const double travel = settings.approach + settings.depths.back() + settings.overshoot;
  const double duration = travel / settings.speed;
  const Eigen::Vector3d start = target - settings.approach * down - tip;
  tool.path = {{0.0, start, turn}, {duration, start + travel * down, turn}};
  press.duration = duration;
  return press;
}

/// Whether a body's shape is still a tissue's, by the limits every run's report judges with:
/// a calibration that took a crumpled or inverted candidate's numbers would fit a model to a
/// state its own run would flag.
class ShapeCheck {
 public:
  explicit ShapeCheck(const TetMesh& mesh) : mesh_(mesh), rest_volume_(mesh_volume(mesh)) {}

  /// Why `positions` is not a tissue's shape; empty when it is.
  std::string operator()(const Eigen::Matrix3Xd& positions) const {
    const PlausibilityLimits limits;
    std::ostringstream why;
    const int inverted = count_inverted_tets(mesh_, positions);
    const double change = std::abs(mesh_volume(mesh_, positions) / rest_volume_ - 1.0);
    if (inverted > limits.max_inverted_fraction * mesh_.num_tets()) {
      why << inverted << " of " << mesh_.num_tets() << " tets inverted";
    } else if (change > limits.max_volume_change) {
      why << "volume changed by " << 100.0 * change << "%";
    }
    return why.str();
  }

 private:
  const TetMesh& mesh_;
  double rest_volume_;
};

/// The force at `depth` past first contact, linear between the steps around it.
double force_at(const std::vector<double>& travel, const std::vector<double>& force, double depth) {
  for (std::size_t k = 1; k < travel.size(); ++k) {
    if (travel[k] >= depth) {
      const double span = travel[k] - travel[k - 1];
      const double w = span > 0.0 ? (depth - travel[k - 1]) / span : 1.0;
      return (1.0 - w) * force[k - 1] + w * force[k];
    }
  }
  return kNaN;
}

}  // namespace

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

namespace {

/// Steps `body` (fresh, at rest) under gravity with the fixed region held until it is at rest.
StaticSag settle(const scenes::Scene& scene,
                 const TetMesh& mesh,
                 SoftBody& body,
                 const StaticSagOptions& options) {
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
  const ShapeCheck check(mesh);
  const int window = static_cast<int>(std::ceil(1.0 / scene.dt));
  const int max_steps = static_cast<int>(std::ceil(options.max_time / scene.dt));
  int slow_steps = 0;
  for (int step = 0; step < max_steps && !result.settled; ++step) {
    if (!monitor.after_step(step, body.step(scene.dt, input), body, pins)) {
      result.stable = false;
      return result;
    }
    slow_steps = monitor.free_speed() < options.rest_speed ? slow_steps + 1 : 0;
    result.settled = slow_steps >= window;
    result.time = (step + 1) * scene.dt;
    result.implausible = check(body.positions());
    if (!result.implausible.empty()) {
      result.settled = false;
      break;
    }
  }
  double sum = 0.0;
  int free_vertices = 0;
  for (int v = 0; v < mesh.num_vertices(); ++v) {
    if (fixed[static_cast<std::size_t>(v)] == 0) {
      sum += (body.positions().col(v) - mesh.rest_positions().col(v)).dot(down);
      ++free_vertices;
    }
  }
  result.sag = free_vertices > 0 ? sum / free_vertices : 0.0;
  result.positions = body.positions();
  return result;
}

}  // namespace

StaticSag static_sag(const scenes::Scene& scene,
                     const TetMesh& mesh,
                     const std::string& model,
                     const nlohmann::json& params,
                     const StaticSagOptions& options) {
  return settle(scene, mesh, *create(scene, mesh, model, params), options);
}

int press_vertex(const scenes::Scene& scene, const TetMesh& mesh) {
  const std::vector<int> fixed = scenes::required_fixed_vertices(
      scene, mesh, "calibrate", "the press is on the body hanging from it");
  std::vector<char> is_fixed(static_cast<std::size_t>(mesh.num_vertices()), 0);
  for (int v : fixed) {
    is_fixed[static_cast<std::size_t>(v)] = 1;
  }
  const Eigen::Matrix3Xd& rest = mesh.rest_positions();
  Eigen::Vector3d centre = Eigen::Vector3d::Zero();
  int count = 0;
  for (int v = 0; v < mesh.num_vertices(); ++v) {
    if (is_fixed[static_cast<std::size_t>(v)] == 0) {
      centre += rest.col(v);
      ++count;
    }
  }
  centre /= std::max(count, 1);
  const Eigen::Vector3d down = scene.gravity.acceleration.normalized();
  const double radius = 0.1 * bounding_box_diagonal(rest);
  std::vector<char> on_surface(static_cast<std::size_t>(mesh.num_vertices()), 0);
  const Eigen::Matrix3Xi faces = boundary_triangles(mesh.tets());
  for (int i = 0; i < faces.size(); ++i) {
    on_surface[static_cast<std::size_t>(faces.data()[i])] = 1;
  }
  // Highest within the radius of the vertical line; failing any, the surface vertex nearest it.
  int best = -1;
  int nearest = -1;
  double best_height = -std::numeric_limits<double>::infinity();
  double nearest_distance = std::numeric_limits<double>::infinity();
  for (int v = 0; v < mesh.num_vertices(); ++v) {
    if (on_surface[static_cast<std::size_t>(v)] == 0 || is_fixed[static_cast<std::size_t>(v)] != 0) {
      continue;
    }
    const Eigen::Vector3d offset = rest.col(v) - centre;
    const double across = (offset - offset.dot(down) * down).norm();
    const double height = -offset.dot(down);
    if (across <= radius && height > best_height) {
      best_height = height;
      best = v;
    }
    if (across < nearest_distance) {
      nearest_distance = across;
      nearest = v;
    }
  }
  return best >= 0 ? best : nearest;
}

TissueResponse tissue_response(const scenes::Scene& scene,
                               const SceneMesh& mesh,
                               const std::string& model,
                               const nlohmann::json& params,
                               const PressSettings& settings) {
  if (!scene.instrument || mesh.instrument == nullptr) {
    throw InputError(scene.source.string()
                     + ": /instrument: calibrate presses the body with the scene's instrument, "
                       "and the scene has none");
  }
  const auto started = std::chrono::steady_clock::now();
  TissueResponse response;
  response.press_vertex = press_vertex(scene, mesh.body);
  // One body settles and then presses: a position-based model's rest state is its own, with
  // its own damping (Bullet's differs with kDP), so it cannot be handed to another body.
  const std::unique_ptr<SoftBody> body =
      create(scene, mesh.body, model, with_settling_damping(model, params));
  response.sag = settle(scene, mesh.body, *body, settings.settling);
  response.forces.assign(settings.depths.size(), kNaN);
  if (!response.sag.implausible.empty()) {
    response.implausible = "under gravity: " + response.sag.implausible;
  } else if (!response.sag.settled) {
    std::ostringstream why;
    why << "still moving after " << response.sag.time << " s under gravity";
    response.implausible = why.str();
  }
  if (!response.sag.stable || !response.sag.implausible.empty()) {
    response.press_stable = response.sag.stable;  // not pressed: a crumpled body has no press
    response.seconds =
        std::chrono::duration<double>(std::chrono::steady_clock::now() - started).count();
    return response;
  }

  const scenes::Scene press = press_scene(
      scene, mesh, response.sag.positions.col(response.press_vertex), settings);
  SceneStepper stepper(press, mesh);
  RunMonitor monitor(mesh.body, press.limits, mesh.diagonal());
  const ShapeCheck check(mesh.body);
  std::vector<double> travel{-settings.approach};
  std::vector<double> force{0.0};
  const int steps = press.num_steps();
  for (int step = 0; step < steps; ++step) {
    const StepStats stats = stepper.step(step, *body);
    if (!monitor.after_step(step, stats, *body, stepper.constraints())) {
      response.press_stable = false;
      break;
    }
    stepper.observe(step, *body);
    travel.push_back(stepper.loading().tool_displacement() - settings.approach);
    force.push_back(stepper.loading().tool_force());
    // The first step that leaves a tissue's shape is named; the press goes on, so that the
    // candidate's forces still rank it among the others that did.
    if (response.implausible.empty()) {
      if (const std::string why = check(body->positions()); !why.empty()) {
        std::ostringstream at;
        at << "pressed " << 100.0 * travel.back() << " cm: " << why;
        response.implausible = at.str();
      }
    }
  }
  for (std::size_t i = 0; i < settings.depths.size(); ++i) {
    response.forces[i] = force_at(travel, force, settings.depths[i]);
  }
  response.seconds =
      std::chrono::duration<double>(std::chrono::steady_clock::now() - started).count();
  return response;
}

nlohmann::json to_json(const TissueResponse& response) {
  nlohmann::json forces = nlohmann::json::array();
  for (double f : response.forces) {
    forces.push_back(std::isfinite(f) ? nlohmann::json(f) : nlohmann::json(nullptr));
  }
  return {{"sag", response.sag.sag},
          {"settled", response.sag.settled},
          {"settle_time", response.sag.time},
          {"stable", response.sag.stable && response.press_stable},
          {"implausible", response.implausible},
          {"press_vertex", response.press_vertex},
          {"forces", forces},
          {"seconds", response.seconds}};
}

TissueResponse tissue_response_from_json(const nlohmann::json& json) {
  TissueResponse response;
  response.sag.sag = json.at("sag").get<double>();
  response.sag.settled = json.at("settled").get<bool>();
  response.sag.time = json.at("settle_time").get<double>();
  response.sag.stable = json.at("stable").get<bool>();
  response.press_stable = response.sag.stable;
  response.implausible = json.at("implausible").get<std::string>();
  response.press_vertex = json.at("press_vertex").get<int>();
  for (const nlohmann::json& f : json.at("forces")) {
    response.forces.push_back(f.is_null() ? kNaN : f.get<double>());
  }
  response.seconds = json.at("seconds").get<double>();
  return response;
}

}  // namespace softbench::harness
