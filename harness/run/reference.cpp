// SPDX-License-Identifier: MIT
#include "harness/run/reference.h"

#include "geometry/atomic_file.h"
#include "geometry/input_error.h"
#include "harness/provenance.h"
#include "harness/run/runner.h"
#include "models/json_reader.h"
#include "models/model_registry.h"
#include "models/json_file.h"

#include <fstream>

namespace softbench::harness {
namespace {

nlohmann::json matrix_json(const Eigen::Matrix3Xd& m) {
  return std::vector<double>(m.data(), m.data() + m.size());
}

Eigen::Matrix3Xd matrix_from(const nlohmann::json& json, Eigen::Index columns) {
  const std::vector<double> values = json.get<std::vector<double>>();
  if (static_cast<Eigen::Index>(values.size()) != 3 * columns) {
    throw InputError("reference cache: expected " + std::to_string(3 * columns) + " coordinates");
  }
  return Eigen::Map<const Eigen::Matrix3Xd>(values.data(), 3, columns);
}

nlohmann::json to_json(const ReferenceRun& reference) {
  nlohmann::json positions = nlohmann::json::array();
  for (const Eigen::Matrix3Xd& x : reference.positions) {
    positions.push_back(matrix_json(x));
  }
  return {{"settings", reference.settings},
          {"times", reference.times},
          {"volumes", reference.volumes},
          {"peak_tool_force", reference.peak_tool_force},
          {"positions", positions}};
}

ReferenceRun reference_from_json(const nlohmann::json& json) {
  ReferenceRun reference;
  reference.settings = json.at("settings");
  reference.times = json.at("times").get<std::vector<double>>();
  reference.volumes = json.at("volumes").get<std::vector<double>>();
  reference.peak_tool_force = json.at("peak_tool_force").get<double>();
  const Eigen::Index vertices = json.at("settings").at("vertices").get<Eigen::Index>();
  for (const nlohmann::json& x : json.at("positions")) {
    reference.positions.push_back(matrix_from(x, vertices));
  }
  if (reference.positions.size() != reference.times.size()) {
    throw InputError("reference cache: positions and times differ in count");
  }
  return reference;
}

}  // namespace

ReferenceRun reference_run(const scenes::Scene& scene,
                           const SceneMesh& mesh,
                           const ReferenceSettings& settings,
                           const std::filesystem::path& cache_dir) {
  if (!builtin_models().contains(settings.model)) {
    throw InputError("reference model \"" + settings.model + "\" is not in this build");
  }
  scenes::Scene fine = scene;
  fine.dt = scene.dt / settings.substeps;
  const nlohmann::json key = {{"scene", scenes::to_json(fine)},
                              {"mesh_hash", mesh.content_hash},
                              {"model", settings.model},
                              {"times", settings.times},
                              {"build", build_fingerprint()}};
  const std::filesystem::path cache = cache_dir / (stable_hash(key.dump()) + ".json");
  if (std::filesystem::exists(cache)) {
    return reference_from_json(read_json_file(cache.string()));
  }

  RunOptions options;
  options.models = {settings.model};
  options.snapshot_times = comparison_times(scene, settings.times);
  const ModelRun run = run_scene(fine, mesh, options).front();
  if (!run.stability.stable || run.snapshots.size() != options.snapshot_times.size()) {
    throw InputError(scene.source.string() + ": the reference (" + settings.model
                     + ") blew up: " + run.stability.divergence);
  }
  ReferenceRun reference;
  reference.settings = key;
  reference.settings["vertices"] = run.vertices;
  for (const Snapshot& snapshot : run.snapshots) {
    reference.times.push_back(snapshot.time);
    reference.positions.push_back(snapshot.positions);
    reference.volumes.push_back(snapshot.volume);
  }
  reference.peak_tool_force = run.contact.peak_tool_force;
  std::filesystem::create_directories(cache_dir);
  const std::string text = to_json(reference).dump() + "\n";
  write_file_atomically(cache, [&](std::ostream& out) { out << text; });
  return reference;
}

}  // namespace softbench::harness
