// SPDX-License-Identifier: MIT
#include "harness/report/comparison_report.h"

#include "geometry/atomic_file.h"
#include "geometry/input_error.h"
#include "harness/provenance.h"
#include "harness/report/model_run_json.h"
#include "harness/report/run_report.h"
#include "models/json_reader.h"

#include <cmath>
#include <iomanip>
#include <limits>
#include <sstream>

namespace softbench::harness {
namespace {

constexpr const char* kSource = "compare.json";

// Steps per second to three significant figures at least, without a pointless fraction.
std::string rate(double value) {
  if (!(value > 0.0)) {
    return "-";
  }
  return fixed(value, value >= 100.0 ? 0 : 1);
}

void scene_table(std::ostream& out, const SceneComparison& scene) {
  out << "## " << scene.name << "\n\n";
  const std::string description = scene.scene.value("description", std::string());
  if (!description.empty()) {
    out << description << "\n\n";
  }
  if (scene.scene.contains("time") && scene.scene.contains("mesh")) {
    out << "Mesh `" << scene.scene["mesh"].get<std::string>() << "`";
    if (!scene.runs.empty()) {
      out << " (" << scene.runs.front().vertices << " vertices, " << scene.runs.front().tets
          << " tets)";
    }
    out << ", dt = " << scene.scene["time"].value("dt", 0.0) << " s, "
        << scene.scene["time"].value("duration", 0.0) << " s.\n\n";
  }
  out << "| model | thesis FPS | steps/s | steps/s with collision | stable | max inverted tets | "
         "recovery residual | time to 1% (s) | max penetration (mm) | peak tool force (N) "
         "| max volume change | warnings |\n";
  out << "|---|---|---|---|---|---|---|---|---|---|---|---|\n";
  for (const ModelRun& run : scene.runs) {
    const std::optional<double> thesis = thesis_steps_per_second(run.model);
    out << "| " << run.model << " | " << (thesis ? fixed(*thesis, 1) : "-") << " | "
        << rate(run.timing.steps_per_second) << " | "
        << rate(run.timing.steps_per_second_with_collision) << " | "
        << (run.stability.stable ? "yes"
                                 : "NO (step "
                                       + (run.stability.diverged_at_step
                                              ? std::to_string(*run.stability.diverged_at_step)
                                              : "?")
                                       + ": " + run.stability.divergence + ")")
        << " | " << run.shape.max_inverted_tets << " | "
        << (run.recovery.measured ? fixed(100.0 * run.recovery.residual, 2) + "%" : "-") << " | "
        << (run.recovery.time_to_one_percent ? fixed(*run.recovery.time_to_one_percent, 2) : "-")
        << " | " << fixed(1000.0 * run.contact.max_penetration, 2) << " | "
        << fixed(run.contact.peak_tool_force, 3) << " | "
        << fixed(100.0 * run.shape.volume_change, 2) << "% | " << warnings_cell(run) << " |\n";
  }
  out << "\n" << warnings_markdown(scene.runs);
}

}  // namespace

nlohmann::json comparison_json(const Comparison& comparison) {
  nlohmann::json json;
  json["softbench_compare"] = kCompareSchemaVersion;
  json["provenance"] = to_json(provenance());
  json["machine"] = comparison.machine;
  json["thesis"] = {
      {"hardware", "Intel Core i3-2100 @ 3.1 GHz, NVIDIA GeForce GTS450, 6 GB (thesis 3.5)"},
      {"note", "frames per second with rendering, one simulation step per frame"},
      {"steps_per_second",
       {{"mass_spring", *thesis_steps_per_second("mass_spring")},
        {"fem", *thesis_steps_per_second("corotational_fem")},
        {"shape_matching", *thesis_steps_per_second("shape_matching")}}}};
  json["criteria"] = {{"recovered_residual", kRecoveredResidual},
                      {"max_inverted_tets", comparison.criteria.max_inverted_tets},
                      {"volume_ratio", comparison.criteria.volume_ratio},
                      {"volume_margin", comparison.criteria.volume_margin}};
  json["scenes"] = nlohmann::json::array();
  for (const SceneComparison& scene : comparison.scenes) {
    nlohmann::json runs = nlohmann::json::array();
    for (const ModelRun& run : scene.runs) {
      nlohmann::json entry = to_json(run);
      const std::optional<double> thesis = thesis_steps_per_second(run.model);
      entry["thesis_steps_per_second"] = thesis ? nlohmann::json(*thesis) : nlohmann::json(nullptr);
      runs.push_back(entry);
    }
    json["scenes"].push_back({{"name", scene.name}, {"scene", scene.scene}, {"runs", runs}});
  }
  json["claims"] = nlohmann::json::array();
  for (const Claim& claim : comparison.claims) {
    json["claims"].push_back(to_json(claim));
  }
  return json;
}

Comparison comparison_from_json(const nlohmann::json& json) {
  const JsonReader root(json, kSource);
  const int version = root.integer("softbench_compare", 0, std::numeric_limits<int>::max());
  if (version != kCompareSchemaVersion) {
    root.fail_expected("softbench_compare", std::to_string(kCompareSchemaVersion));
  }
  Comparison comparison;
  comparison.machine = root.string("machine");
  const JsonReader criteria = root.object("criteria");
  comparison.criteria.max_inverted_tets =
      criteria.integer("max_inverted_tets", 0, std::numeric_limits<int>::max());
  comparison.criteria.volume_ratio = criteria.number("volume_ratio");
  comparison.criteria.volume_margin = criteria.number("volume_margin");
  for (const JsonReader& scene_in : root.objects("scenes")) {
    SceneComparison scene;
    scene.name = scene_in.string("name");
    scene.scene = scene_in.raw("scene");
    for (const JsonReader& run_in : scene_in.objects("runs")) {
      scene.runs.push_back(model_run_from_json(run_in));
    }
    comparison.scenes.push_back(std::move(scene));
  }
  for (const JsonReader& claim_in : root.objects("claims")) {
    comparison.claims.push_back(claim_from_json(claim_in));
  }
  return comparison;
}

std::string comparison_markdown(const Comparison& comparison) {
  std::ostringstream out;
  out << "# softbench compare: the thesis's chapter-3 comparison\n\n";
  out << "Ours: steps per second of `step()` alone (\"steps/s\") and of `step()` plus the step's "
         "collision work (BVH refit, query, contact constraints), medians over the steps after "
         "warm-up, on "
      << comparison.machine
      << ". The thesis's: frames per second with rendering on an Intel Core i3-2100 @ 3.1 GHz, "
         "one step per frame, on its own liver mesh (section 3.5.1; its \"FEM\" figure stands "
         "beside both FEM rows). Residuals are RMS distances to the shape before the load, over "
         "the rest bounding-box diagonal, at the end of the run. The tool is the instrument, else "
         "the "
         "grasp; its force is the sum of the constraint forces the tissue exerts on it. "
         "\"warnings\" names the plausibility checks a run failed although it stayed stable "
         "(harness/run/plausibility.h); each is explained under its table.\n\n";
  for (const SceneComparison& scene : comparison.scenes) {
    scene_table(out, scene);
  }
  out << "## The thesis's claims (section 3.5.2)\n\n";
  for (const Claim& claim : comparison.claims) {
    out << claim_markdown(claim);
  }
  return out.str();
}

void write_comparison(const std::filesystem::path& out_dir, const Comparison& comparison) {
  std::filesystem::create_directories(out_dir);
  const std::string json = comparison_json(comparison).dump(1) + "\n";
  write_file_atomically(out_dir / "compare.json", [&](std::ostream& out) { out << json; });
  const std::string markdown = comparison_markdown(comparison);
  write_file_atomically(out_dir / "compare.md", [&](std::ostream& out) { out << markdown; });
}

}  // namespace softbench::harness
