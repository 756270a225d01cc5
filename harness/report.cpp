// SPDX-License-Identifier: MIT
#include "harness/report.h"

#include "geometry/atomic_file.h"

#include <cmath>
#include <iomanip>
#include <sstream>

namespace softbench::harness {
std::string fixed(double value, int digits) {
  std::ostringstream out;
  out << std::fixed << std::setprecision(digits) << value;
  return out.str();
}

nlohmann::json number_or_null(double value) {
  return std::isfinite(value) ? nlohmann::json(value) : nlohmann::json(nullptr);
}

nlohmann::json to_json(const ModelRun& run) {
  nlohmann::json json;
  json["model"] = run.model;
  json["params"] = run.params;
  json["mesh"] = {{"vertices", run.vertices}, {"tets", run.tets}};
  json["steps"] = run.steps_run;
  json["steps_planned"] = run.steps_planned;
  json["step_ms"] = {
      {"median", run.step_ms.median}, {"p95", run.step_ms.p95}, {"max", run.step_ms.max}};
  json["fps"] = run.fps;
  json["fps_with_collision"] = run.fps_with_collision;
  json["step_with_collision_ms"] = {{"median", run.step_with_collision_ms.median},
                                    {"p95", run.step_with_collision_ms.p95},
                                    {"max", run.step_with_collision_ms.max}};
  json["contact"] = {{"max_penetration", run.max_penetration},
                     {"max_penetration_pressing", run.max_penetration_pressing},
                     {"lost_contact_vertices", run.lost_contact_vertices},
                     {"max_triangle_pairs", run.max_triangle_pairs},
                     {"peak_tool_force", run.peak_tool_force}};
  // Columns rather than records: a few hundred steps stay readable and small.
  nlohmann::json series = {{"time", nlohmann::json::array()},
                           {"tool_displacement", nlohmann::json::array()},
                           {"tool_force", nlohmann::json::array()},
                           {"recovery_residual", nlohmann::json::array()}};
  for (const StepSample& sample : run.samples) {
    series["time"].push_back(sample.time);
    series["tool_displacement"].push_back(sample.tool_displacement);
    series["tool_force"].push_back(sample.tool_force);
    series["recovery_residual"].push_back(number_or_null(sample.recovery_residual));
  }
  json["series"] = series;
  json["stable"] = run.stable;
  json["diverged_at_step"] =
      run.diverged_at_step ? nlohmann::json(*run.diverged_at_step) : nlohmann::json(nullptr);
  json["divergence"] = run.divergence;
  json["max_inverted_tets"] = run.max_inverted_tets;
  json["volume_change"] = run.volume_change;
  json["max_speed"] = run.max_speed;
  json["energy"] = {{"max_kinetic", run.max_kinetic_energy},
                    {"final_elastic", number_or_null(run.final_elastic_energy)}};
  if (run.recovery_measured) {
    json["recovery"] = {{"residual_rms_rel", run.recovery_residual},
                        {"time_to_1pct_s", run.time_to_1pct ? nlohmann::json(*run.time_to_1pct)
                                                            : nlohmann::json(nullptr)}};
  } else {
    json["recovery"] = nullptr;
  }
  if (run.accuracy) {
    const Accuracy& a = *run.accuracy;
    json["accuracy"] = {
        {"rms_error", number_or_null(a.rms_error)},
        {"max_error", number_or_null(a.max_error)},
        {"volume_error", number_or_null(a.volume_error)},
        {"peak_force_error",
         a.peak_force_error ? number_or_null(*a.peak_force_error) : nlohmann::json(nullptr)}};
  } else {
    json["accuracy"] = nullptr;  // the scene asks for no accuracy: no reference was run
  }
  json["solver"] = {{"mean_iterations", run.mean_iterations},
                    {"factorizations", run.factorizations},
                    {"linear_solves", run.linear_solves},
                    {"max_constraint_error", run.max_constraint_error}};
  json["final_reaction_sum"] = {run.final_reaction_sum.x(), run.final_reaction_sum.y(),
                                run.final_reaction_sum.z()};
  json["memory_bytes"] = run.memory_bytes;
  return json;
}

nlohmann::json metrics_json(const scenes::Scene& scene, const std::vector<ModelRun>& runs) {
  nlohmann::json json;
  json["scene"] = scenes::to_json(scene);
  json["runs"] = nlohmann::json::array();
  for (const ModelRun& run : runs) {
    json["runs"].push_back(to_json(run));
  }
  return json;
}

std::string summary_markdown(const scenes::Scene& scene, const std::vector<ModelRun>& runs) {
  std::ostringstream out;
  out << "# " << scene.name << "\n\n";
  if (!scene.description.empty()) {
    out << scene.description << "\n\n";
  }
  out << "dt = " << scene.dt << " s, " << scene.num_steps() << " steps; step times are medians "
      << "over the steps after warm-up, measured around step() only.\n\n";
  out << "| model | stable | steps/s | steps/s with collision | step ms (median / p95 / max) | "
         "iterations | max inverted tets | max volume change | recovery residual | "
         "time to 1% (s) | max penetration (mm) | peak tool force (N) |\n";
  out << "|---|---|---|---|---|---|---|---|---|---|---|---|\n";
  for (const ModelRun& run : runs) {
    out << "| " << run.model << " | "
        << (run.stable
                ? "yes"
                : "NO (step " + std::to_string(*run.diverged_at_step) + ": " + run.divergence + ")")
        << " | " << fixed(run.fps, 0) << " | " << fixed(run.fps_with_collision, 0) << " | "
        << fixed(run.step_ms.median, 3) << " / " << fixed(run.step_ms.p95, 3) << " / "
        << fixed(run.step_ms.max, 3) << " | " << fixed(run.mean_iterations, 1) << " | "
        << run.max_inverted_tets << " | " << fixed(100.0 * run.volume_change, 2) << "% | "
        << (run.recovery_measured ? fixed(100.0 * run.recovery_residual, 2) + "%" : "-") << " | "
        << (run.time_to_1pct ? fixed(*run.time_to_1pct, 2) : "-") << " | "
        << fixed(1000.0 * run.max_penetration, 2) << " | " << fixed(run.peak_tool_force, 3)
        << " |\n";
  }
  return out.str();
}

void write_reports(const std::filesystem::path& out_dir,
                   const scenes::Scene& scene,
                   const std::vector<ModelRun>& runs) {
  std::filesystem::create_directories(out_dir);
  const std::string metrics = metrics_json(scene, runs).dump(2) + "\n";
  write_file_atomically(out_dir / "metrics.json", [&](std::ostream& out) { out << metrics; });
  const std::string summary = summary_markdown(scene, runs);
  write_file_atomically(out_dir / "summary.md", [&](std::ostream& out) { out << summary; });
}

}  // namespace softbench::harness
