// SPDX-License-Identifier: MIT
// Scene files (scenes/README.md is the schema) to the plain structs of scene.h and back. Every
// check goes through JsonReader so each message reads `<file>: <json pointer>: expected ...,
// got ...`.
#include "geometry/input_error.h"
#include "geometry/text_format.h"
#include "models/json_reader.h"
#include "models/material.h"
#include "models/json_file.h"
#include "scenes/scene.h"

#include <Eigen/Core>
#include <Eigen/Geometry>
#include <nlohmann/json.hpp>

#include <algorithm>
#include <cmath>
#include <cstddef>
#include <filesystem>
#include <initializer_list>
#include <limits>
#include <map>
#include <numbers>
#include <sstream>
#include <string>
#include <string_view>
#include <system_error>
#include <vector>

namespace softbench::scenes {
namespace {

namespace fs = std::filesystem;

constexpr double kDefaultTimeStep = 1.0 / 60.0;  // s: the thesis's frame rate

nlohmann::json vector_json(const Eigen::Vector3d& value) {
  return nlohmann::json::array({value.x(), value.y(), value.z()});
}

// Declares the keys `in` may hold and rejects any other before a value is read, so a misspelt
// optional key is not silently ignored, a misspelt required key is reported as unknown rather
// than as missing, and the message lists every key allowed there.
void allow_only(const JsonReader& in, std::initializer_list<std::string_view> keys) {
  for (const std::string_view key : keys) {
    in.find(key);
  }
  in.reject_unknown_keys();
}

std::string string_or(const JsonReader& in, std::string_view key, const std::string& fallback) {
  const nlohmann::json* value = in.find(key);
  if (value == nullptr) {
    return fallback;
  }
  if (!value->is_string()) {
    in.fail_expected(key, "a string");
  }
  return value->get<std::string>();
}

// A file named relative to the scene file's folder (or absolute), which must exist.
fs::path existing_file(const JsonReader& in, std::string_view key, const fs::path& folder) {
  const std::string written = in.string(key);
  if (written.empty()) {
    in.fail_expected(key, "a file path");
  }
  const fs::path resolved = (folder / written).lexically_normal();
  std::error_code error;
  if (!fs::is_regular_file(resolved, error)) {
    in.fail(key, "file not found: " + one_line(resolved.string()));
  }
  return resolved;
}

// The inverse of existing_file(): the path relative to `source`'s folder when that names it
// (lexically_relative cannot see through a ".." in the folder), else absolute.
std::string path_as_written(const fs::path& resolved, const fs::path& source) {
  const fs::path folder = source.parent_path();
  const fs::path relative = resolved.lexically_relative(folder);
  if (!relative.empty() && (folder / relative).lexically_normal() == resolved) {
    return relative.string();
  }
  return fs::absolute(resolved).lexically_normal().string();
}

Material read_material(const JsonReader& root) {
  const JsonReader in = root.object("material");
  allow_only(in, {"young_modulus", "poisson_ratio", "density"});
  Material material;
  material.young_modulus = in.number("young_modulus");
  material.poisson_ratio = in.number("poisson_ratio");
  material.density = in.number("density");
  validate_material(material, root.source() + ": /material");
  return material;
}

Gravity read_gravity(const JsonReader& root) {
  Gravity gravity;
  const nlohmann::json* value = root.find("gravity");
  if (value == nullptr) {
    return gravity;
  }
  if (value->is_array()) {
    gravity.acceleration = root.vector3("gravity");
    return gravity;
  }
  if (!value->is_object()) {
    root.fail_expected("gravity", "[x, y, z] or {\"acceleration\": [x, y, z], \"off_at\": t}");
  }
  const JsonReader in = root.object("gravity");
  allow_only(in, {"acceleration", "off_at"});
  gravity.acceleration = in.vector3_or("acceleration", gravity.acceleration);
  gravity.off_at = in.number_or("off_at", kNever, Range::non_negative());
  return gravity;
}

void read_time(const JsonReader& root, Scene& scene) {
  const JsonReader in = root.object("time");
  allow_only(in, {"dt", "duration"});
  scene.duration = in.number("duration", Range::positive());
  scene.dt = in.number_or("dt", kDefaultTimeStep, Range::positive());
  if (scene.dt > scene.duration) {
    in.fail_expected("dt", "a number <= duration (" + format_number(scene.duration) + ")");
  }
  const double steps = step_count(scene.duration, scene.dt);
  if (steps > kMaxSteps) {
    in.fail("duration", format_number(scene.duration) + " s at dt = " + format_number(scene.dt)
                            + " s is " + format_number(steps, 3) + " steps, over the limit of "
                            + std::to_string(kMaxSteps) + " (shorten duration or raise dt)");
  }
}

Box read_box(const JsonReader& in) {
  allow_only(in, {"min", "max"});
  Box box;
  box.min = in.vector3("min");
  box.max = in.vector3("max");
  if (!(box.min.array() <= box.max.array()).all()) {
    in.fail_expected("max", "[x, y, z] >= min " + format_vector(box.min) + " in every coordinate");
  }
  return box;
}

Plane read_plane(const JsonReader& in) {
  allow_only(in, {"point", "normal", "tolerance"});
  Plane plane;
  plane.point = in.vector3("point");
  const Eigen::Vector3d normal = in.vector3("normal");
  const double length = normal.stableNorm();
  if (!(length > 0.0) || !std::isfinite(length)) {
    in.fail_expected("normal", "a non-zero [x, y, z]");
  }
  plane.normal = normal / length;
  plane.tolerance = in.number_or("tolerance", 0.0, Range::non_negative());
  return plane;
}

// Absent, or selecting nothing: a free body.
FixedRegion read_fixed(const JsonReader& root) {
  FixedRegion fixed;
  if (!root.has("fixed")) {
    return fixed;
  }
  const JsonReader in = root.object("fixed");
  allow_only(in, {"vertices", "box", "plane"});
  if (in.has("vertices")) {
    fixed.vertices = in.integers("vertices", 0, std::numeric_limits<int>::max());
  }
  if (in.has("box")) {
    fixed.box = read_box(in.object("box"));
  }
  if (in.has("plane")) {
    fixed.plane = read_plane(in.object("plane"));
  }
  return fixed;
}

std::vector<Plane> read_supports(const JsonReader& root) {
  std::vector<Plane> supports;
  if (root.has("supports")) {
    for (const JsonReader& in : root.objects("supports")) {
      supports.push_back(read_plane(in));
    }
  }
  return supports;
}

InitialVelocity read_initial_velocity(const JsonReader& root) {
  const JsonReader in = root.object("initial_velocity");
  allow_only(in, {"linear", "angular", "center"});
  if (!in.has("linear") && !in.has("angular")) {
    root.fail_expected("initial_velocity", "at least one of \"linear\", \"angular\"");
  }
  InitialVelocity velocity;
  velocity.linear = in.vector3_or("linear", velocity.linear);
  velocity.angular = in.vector3_or("angular", velocity.angular);
  if (in.has("center")) {
    velocity.center = in.vector3("center");
  }
  return velocity;
}

Grasp read_grasp(const JsonReader& root) {
  const JsonReader in = root.object("grasp");
  allow_only(in, {"center", "radius", "start", "release", "path"});
  Grasp grasp;
  grasp.center = in.vector3("center");
  grasp.radius = in.number_or("radius", grasp.radius, Range::positive());
  grasp.start = in.number_or("start", grasp.start, Range::non_negative());
  if (in.has("release")) {
    grasp.release = in.number("release", Range::non_negative());
    if (grasp.release <= grasp.start) {
      in.fail_expected("release", "a number > start (" + format_number(grasp.start) + ")");
    }
  }
  if (!in.has("path")) {
    return grasp;
  }
  const std::string window = grasp.release == kNever
                                 ? "a number >= start (" + format_number(grasp.start) + ")"
                                 : "a number in [start, release] = [" + format_number(grasp.start)
                                       + ", " + format_number(grasp.release) + "]";
  for (const JsonReader& key : in.objects("path")) {
    allow_only(key, {"t", "offset"});
    GraspKeyframe frame;
    frame.time = key.number("t", Range::non_negative());
    if (frame.time < grasp.start || frame.time > grasp.release) {
      key.fail_expected("t", window);
    }
    if (!grasp.path.empty() && frame.time <= grasp.path.back().time) {
      key.fail_expected("t", "a number > " + format_number(grasp.path.back().time)
                                 + " (the previous keyframe's t)");
    }
    frame.offset = key.vector3("offset");
    grasp.path.push_back(frame);
  }
  return grasp;
}

Eigen::Quaterniond read_rotation(const JsonReader& key) {
  if (!key.has("rotation")) {
    return Eigen::Quaterniond::Identity();
  }
  const JsonReader in = key.object("rotation");
  allow_only(in, {"axis", "degrees"});
  const Eigen::Vector3d axis = in.vector3("axis");
  // stableNorm: 1e200 squared overflows (norm() gives inf, normalized() zeros, the rotation
  // became the identity) and 1e-200 squared underflows to a "zero" axis.
  if (axis.stableNorm() == 0.0) {
    in.fail_expected("axis", "a non-zero vector");
  }
  // Whole turns dropped first (fmod is exact): 1e308 degrees times pi overflowed to an infinite
  // angle, a NaN orientation.
  const double degrees = std::fmod(in.number("degrees"), 360.0);
  return Eigen::Quaterniond(
      Eigen::AngleAxisd(degrees * std::numbers::pi / 180.0, axis.stableNormalized()));
}

InstrumentGrasp read_instrument_grasp(const JsonReader& instrument) {
  const JsonReader in = instrument.object("grasp");
  allow_only(in, {"center", "radius", "start", "release"});
  InstrumentGrasp grasp;
  grasp.center = in.vector3("center");
  grasp.radius = in.number_or("radius", grasp.radius, Range::positive());
  grasp.start = in.number("start", Range::non_negative());
  grasp.release = in.number("release", Range::non_negative());
  if (grasp.release <= grasp.start) {
    in.fail_expected("release", "a number > start (" + format_number(grasp.start) + ")");
  }
  return grasp;
}

Instrument read_instrument(const JsonReader& root, const fs::path& folder) {
  const JsonReader in = root.object("instrument");
  allow_only(in,
             {"mesh", "path", "grasp", "start", "release", "contact_margin", "contact_passes"});
  Instrument instrument;
  instrument.mesh = existing_file(in, "mesh", folder);
  const std::vector<JsonReader> keys = in.objects("path");
  if (keys.empty()) {
    in.fail_expected("path", "at least one keyframe");
  }
  for (const JsonReader& key : keys) {
    allow_only(key, {"t", "position", "rotation"});
    InstrumentKeyframe frame;
    frame.time = key.number("t", Range::non_negative());
    if (!instrument.path.empty() && frame.time <= instrument.path.back().time) {
      key.fail_expected("t", "a number > " + format_number(instrument.path.back().time)
                                 + " (the previous keyframe's t)");
    }
    frame.position = key.vector3("position");
    frame.orientation = read_rotation(key);
    instrument.path.push_back(frame);
  }
  instrument.contact_margin =
      in.number_or("contact_margin", instrument.contact_margin, Range::positive());
  instrument.contact_passes =
      in.integer_or("contact_passes", instrument.contact_passes, 1, kMaxContactPasses);
  instrument.start = in.number_or("start", instrument.path.front().time, Range::non_negative());
  if (in.has("grasp")) {
    instrument.grasp = read_instrument_grasp(in);
    if (in.has("release")) {
      in.fail("release", "an instrument with a grasp is released by /instrument/grasp/release");
    }
    instrument.release = instrument.grasp->release;
  } else if (in.has("release")) {
    instrument.release = in.number("release", Range::non_negative());
  }
  if (instrument.release <= instrument.start) {
    in.fail_expected("release", "a time > start (" + format_number(instrument.start) + ")");
  }
  return instrument;
}

Requirements read_requirements(const JsonReader& root) {
  const JsonReader in = root.object("requirements");
  allow_only(in, {"steps_per_second", "accuracy", "outputs"});
  Requirements requirements;
  requirements.steps_per_second =
      in.number_or("steps_per_second", requirements.steps_per_second, Range::non_negative());
  if (in.has("accuracy")) {
    requirements.accuracy = in.number("accuracy", Range::positive());
  }
  if (in.has("outputs")) {
    requirements.outputs.clear();
    const nlohmann::json& outputs = in.raw("outputs");
    if (!outputs.is_array() || outputs.empty()) {
      in.fail_expected("outputs",
                       "a non-empty array of \"surface\", \"volume\", \"contact_force\"");
    }
    for (const nlohmann::json& output : outputs) {
      if (!output.is_string()
          || (output != "surface" && output != "volume" && output != "contact_force")) {
        in.fail_expected("outputs",
                         "a non-empty array of \"surface\", \"volume\", \"contact_force\"");
      }
      requirements.outputs.push_back(output.get<std::string>());
    }
  }
  return requirements;
}

StabilityLimits read_limits(const JsonReader& root) {
  StabilityLimits limits;
  if (!root.has("limits")) {
    return limits;
  }
  const JsonReader in = root.object("limits");
  allow_only(in, {"max_speed", "max_displacement"});
  limits.max_speed = in.number_or("max_speed", limits.max_speed, Range::positive());
  limits.max_displacement =
      in.number_or("max_displacement", limits.max_displacement, Range::positive());
  return limits;
}

std::map<std::string, nlohmann::json> read_models(const JsonReader& root) {
  std::map<std::string, nlohmann::json> blocks;
  if (!root.has("models")) {
    return blocks;
  }
  const JsonReader in = root.object("models");
  for (const auto& [name, block] : root.raw("models").items()) {
    if (!block.is_object()) {
      in.fail_expected(name, "an object (the model's parameters)");
    }
    blocks.emplace(name, block);
  }
  return blocks;
}

}  // namespace

nlohmann::json Scene::parameters_for(const std::string& model) const {
  const auto block = model_parameters.find(model);
  return block == model_parameters.end() || block->second.is_null() ? nlohmann::json::object()
                                                                    : block->second;
}

void Scene::override_parameters(const std::string& model, const nlohmann::json& settings) {
  nlohmann::json& block = model_parameters[model];
  if (!block.is_object()) {
    block = nlohmann::json::object();
  }
  block.update(settings);
}

// 3.5 s at dt = 1/60 is 210.00000000000003 steps in floating point: a ratio within rounding of
// an integer counts as that integer, so a dt that divides the duration adds no extra step.
double step_count(double duration, double dt) {
  const double ratio = duration / dt;
  const double nearest = std::round(ratio);
  constexpr double kRelativeSlack = 1e-9;
  if (std::abs(ratio - nearest) <= kRelativeSlack * std::max(1.0, nearest)) {
    return nearest;
  }
  return std::ceil(ratio);
}

int Scene::num_steps() const {
  return static_cast<int>(step_count(duration, dt));
}

double Scene::release_time() const {
  if (grasp) {
    return grasp->release;
  }
  if (instrument) {
    return instrument->release;
  }
  return gravity.off_at;
}

double Scene::reference_time() const {
  if (grasp) {
    return grasp->start;
  }
  if (instrument) {
    return instrument->start;
  }
  return 0.0;
}

Scene load_scene(const std::filesystem::path& path) {
  return parse_scene(read_json_file(path, "scene file"), path);
}

Scene parse_scene(const nlohmann::json& json, const std::filesystem::path& source) {
  const JsonReader root(json, source.string());
  allow_only(root, {"name", "description", "mesh", "material", "gravity", "time", "fixed",
                    "supports", "initial_velocity", "grasp", "instrument", "limits", "requirements", "models"});
  const fs::path folder = source.parent_path();
  Scene scene;
  scene.source = source;
  scene.name = root.string("name");
  if (scene.name.empty()) {
    root.fail_expected("name", "a non-empty string");
  }
  scene.description = string_or(root, "description", "");
  scene.mesh = existing_file(root, "mesh", folder);
  scene.material = read_material(root);
  scene.gravity = read_gravity(root);
  read_time(root, scene);
  scene.fixed = read_fixed(root);
  scene.supports = read_supports(root);
  if (root.has("initial_velocity")) {
    scene.initial_velocity = read_initial_velocity(root);
  }
  if (root.has("grasp")) {
    scene.grasp = read_grasp(root);
  }
  if (root.has("instrument")) {
    scene.instrument = read_instrument(root, folder);
    // One grasp per scene: a grasped patch cannot both stay put and ride on the instrument.
    if (scene.grasp && scene.instrument->grasp) {
      root.fail("grasp", "a scene grasp and an instrument grasp together; keep one");
    }
  }
  scene.limits = read_limits(root);
  if (root.has("requirements")) {
    scene.requirements = read_requirements(root);
  }
  scene.model_parameters = read_models(root);
  return scene;
}

nlohmann::json to_json(const Scene& scene) {
  nlohmann::json json;
  json["name"] = scene.name;
  json["description"] = scene.description;
  json["mesh"] = path_as_written(scene.mesh, scene.source);
  json["material"] = {{"young_modulus", scene.material.young_modulus},
                      {"poisson_ratio", scene.material.poisson_ratio},
                      {"density", scene.material.density}};
  // JSON has no infinity: a time that never comes is left out, as in a scene file.
  json["gravity"] = {{"acceleration", vector_json(scene.gravity.acceleration)}};
  if (scene.gravity.off_at != kNever) {
    json["gravity"]["off_at"] = scene.gravity.off_at;
  }
  json["time"] = {{"dt", scene.dt}, {"duration", scene.duration}};

  nlohmann::json fixed = {{"vertices", scene.fixed.vertices}};
  if (scene.fixed.box) {
    fixed["box"] = {{"min", vector_json(scene.fixed.box->min)},
                    {"max", vector_json(scene.fixed.box->max)}};
  }
  if (scene.fixed.plane) {
    fixed["plane"] = {{"point", vector_json(scene.fixed.plane->point)},
                      {"normal", vector_json(scene.fixed.plane->normal)},
                      {"tolerance", scene.fixed.plane->tolerance}};
  }
  json["fixed"] = fixed;
  // Absent without supports, so the echo of a scene without them is what it was.
  for (const Plane& plane : scene.supports) {
    json["supports"].push_back({{"point", vector_json(plane.point)},
                                {"normal", vector_json(plane.normal)},
                                {"tolerance", plane.tolerance}});
  }
  // Absent without an initial velocity, so the echo of a scene without one is what it was.
  if (scene.initial_velocity) {
    json["initial_velocity"] = {{"linear", vector_json(scene.initial_velocity->linear)},
                                {"angular", vector_json(scene.initial_velocity->angular)}};
    if (scene.initial_velocity->center) {
      json["initial_velocity"]["center"] = vector_json(*scene.initial_velocity->center);
    }
  }

  if (scene.grasp) {
    const Grasp& grasp = *scene.grasp;
    nlohmann::json path = nlohmann::json::array();
    for (const GraspKeyframe& frame : grasp.path) {
      path.push_back({{"t", frame.time}, {"offset", vector_json(frame.offset)}});
    }
    json["grasp"] = {{"center", vector_json(grasp.center)},
                     {"radius", grasp.radius},
                     {"start", grasp.start},
                     {"path", path}};
    if (grasp.release != kNever) {
      json["grasp"]["release"] = grasp.release;
    }
  }

  if (scene.instrument) {
    const Instrument& instrument = *scene.instrument;
    nlohmann::json path = nlohmann::json::array();
    for (const InstrumentKeyframe& frame : instrument.path) {
      const Eigen::AngleAxisd rotation(frame.orientation);
      path.push_back({{"t", frame.time},
                      {"position", vector_json(frame.position)},
                      {"rotation",
                       {{"axis", vector_json(rotation.axis())},
                        {"degrees", rotation.angle() * 180.0 / std::numbers::pi}}}});
    }
    json["instrument"] = {{"mesh", path_as_written(instrument.mesh, scene.source)},
                          {"path", path},
                          {"start", instrument.start},
                          {"contact_margin", instrument.contact_margin},
                          {"contact_passes", instrument.contact_passes}};
    if (instrument.grasp) {
      json["instrument"]["grasp"] = {{"center", vector_json(instrument.grasp->center)},
                                     {"radius", instrument.grasp->radius},
                                     {"start", instrument.grasp->start},
                                     {"release", instrument.grasp->release}};
    } else if (instrument.release != kNever) {
      json["instrument"]["release"] = instrument.release;
    }
  }

  json["limits"] = {{"max_speed", scene.limits.max_speed},
                    {"max_displacement", scene.limits.max_displacement}};
  if (scene.requirements) {
    json["requirements"] = {{"steps_per_second", scene.requirements->steps_per_second},
                            {"outputs", scene.requirements->outputs}};
    if (scene.requirements->accuracy) {
      json["requirements"]["accuracy"] = *scene.requirements->accuracy;
    }
  }
  json["models"] = nlohmann::json::object();
  for (const auto& [name, block] : scene.model_parameters) {
    json["models"][name] = block;
  }
  return json;
}

}  // namespace softbench::scenes
