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
#include <limits>
#include <sstream>

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

ReferenceConvergence reference_convergence(const scenes::Scene& scene,
                                           const SceneMesh& mesh,
                                           const ReferenceSettings& settings,
                                           const std::filesystem::path& cache_dir,
                                           const ReferenceRun& reference) {
  ReferenceSettings finer = settings;
  finer.substeps = 2 * settings.substeps;
  const ReferenceRun fine = reference_run(scene, mesh, finer, cache_dir);
  std::vector<Snapshot> snapshots;
  for (std::size_t i = 0; i < reference.times.size(); ++i) {
    snapshots.push_back({reference.times[i], reference.positions[i], reference.volumes[i]});
  }
  ReferenceConvergence convergence;
  convergence.checked = true;
  convergence.substeps = settings.substeps;
  convergence.finer_substeps = finer.substeps;
  convergence.difference =
      accuracy_against(snapshots, reference.peak_tool_force, fine, mesh.body.rest_positions())
          .rms_error;
  if (scene.requirements && scene.requirements->accuracy) {
    convergence.budget = *scene.requirements->accuracy;
    convergence.budget_from_scene = true;
  }
  return convergence;
}

std::string ranking_refusal(const ReferenceConvergence& convergence) {
  if (!convergence.checked || convergence.converged()) {
    return "";
  }
  std::ostringstream why;
  why << "the reference has not converged: at " << convergence.substeps << " and "
      << convergence.finer_substeps << " substeps it differs by " << 100.0 * convergence.difference
      << "% (rms), more than the " << 100.0 * convergence.budget
      << (convergence.budget_from_scene ? "% the scene requires"
                                        : "% a scene without an accuracy requirement is held to")
      << "; the models' errors against it are its own. Damp the scene, raise "
         "--reference-substeps, or rank anyway with --trust-reference";
  return why.str();
}

nlohmann::json to_json(const ReferenceConvergence& convergence) {
  return {{"checked", convergence.checked},
          {"substeps", convergence.substeps},
          {"finer_substeps", convergence.finer_substeps},
          {"difference", convergence.difference},
          {"budget", convergence.budget},
          {"budget_from_scene", convergence.budget_from_scene},
          {"converged", convergence.converged()}};
}

ReferenceConvergence reference_convergence_from_json(const nlohmann::json& json,
                                                     const std::string& where) {
  try {
    ReferenceConvergence convergence;
    convergence.checked = json.at("checked").get<bool>();
    convergence.substeps = json.at("substeps").get<int>();
    convergence.finer_substeps = json.at("finer_substeps").get<int>();
    // A difference that is not finite was written as null.
    convergence.difference = json.at("difference").is_null()
                                 ? std::numeric_limits<double>::infinity()
                                 : json.at("difference").get<double>();
    convergence.budget = json.at("budget").get<double>();
    convergence.budget_from_scene = json.at("budget_from_scene").get<bool>();
    return convergence;
  } catch (const nlohmann::json::exception& error) {
    throw InputError(where + ": not a reference convergence record: " + error.what());
  }
}

}  // namespace softbench::harness
