// SPDX-License-Identifier: MIT
#include "harness/report/comparison_report.h"

#include "harness/report/comparison_pictures.h"
#include "harness/report/report_files.h"
#include "geometry/input_error.h"
#include "harness/provenance.h"
#include "harness/report/model_run_json.h"
#include "harness/report/run_report.h"
#include "models/json_reader.h"

#include <algorithm>
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

std::string signed_percent(double fraction) {
  if (!std::isfinite(fraction)) {
    return "-";
  }
  std::string text = fraction >= 0.0 ? "+" : "";
  text += fixed(100.0 * fraction, 0);
  text += '%';
  return text;
}

// "alpha 0.31, beta 0.2 (sag +3%, force at 0.5 cm -12%, ...)" for a calibrated row.
std::string calibration_cell(const nlohmann::json& calibration) {
  std::ostringstream out;
  bool first = true;
  for (const auto& [name, value] : calibration.at("values").items()) {
    out << (first ? "" : ", ") << name << " " << std::setprecision(3) << value.get<double>();
    first = false;
  }
  const auto& targets = calibration.at("targets");
  const auto& errors = calibration.at("errors");
  out << " (";
  for (std::size_t i = 0; i < targets.size() && i < errors.size(); ++i) {
    out << (i == 0 ? "" : ", ") << targets[i].get<std::string>() << " "
        << signed_percent(errors[i].get<double>());
  }
  out << ")";
  return out.str();
}

void matched_table(std::ostream& out, const MatchedScene& scene, double dt) {
  out << "### " << scene.name << ", matched to the tissue\n\n";
  out << "| model | calibration (fitted; error left on each target) | steps/s with collision | "
         "real-time factor | position error (% of diagonal) | position error (% of the "
         "reference's displacement) | peak tool force (N) | peak force error | stable | "
         "warnings |\n";
  out << "|---|---|---|---|---|---|---|---|---|---|\n";
  for (const ModelRun& run : scene.runs) {
    const auto calibration = scene.calibrations.find(run.model);
    const Accuracy accuracy = run.accuracy.value_or(Accuracy{});
    const double per_second = run.timing.steps_per_second_with_collision;
    out << "| " << run.model << " | "
        << (calibration == scene.calibrations.end() ? std::string("follows the material")
                                                     : calibration_cell(calibration->second))
        << " | " << rate(per_second) << " | "
        << (per_second > 0.0 && dt > 0.0 ? fixed(per_second * dt, 2) + "x" : "-") << " | "
        << (std::isfinite(accuracy.diagonal_error) ? fixed(100.0 * accuracy.diagonal_error, 2)
                                                   : "-")
        << " | "
        << (std::isfinite(accuracy.rms_error) ? fixed(100.0 * accuracy.rms_error, 1) : "-")
        << " | " << fixed(run.contact.peak_tool_force, 3) << " | "
        << (accuracy.peak_force_error ? signed_percent(*accuracy.peak_force_error) : "-")
        << " | " << (run.stability.stable ? "yes" : "NO") << " | " << warnings_cell(run)
        << " |\n";
  }
  out << "\n";
  for (const std::string& note : scene.notes) {
    out << "- " << note << "\n";
  }
  if (!scene.notes.empty()) {
    out << "\n";
  }
  out << "Speed against corotational_fem (steps/s with collision), the thesis's and ours:";
  for (const SpeedRatio& ratio : speed_ratios(scene.runs)) {
    out << " " << ratio.label << " / FEM: thesis " << fixed(ratio.thesis, 1) << ", ours "
        << (ratio.ours ? fixed(*ratio.ours, 2) : std::string("-")) << ";";
  }
  out << "\n\n" << warnings_markdown(scene.runs);
}

nlohmann::json matched_json(const MatchedScene& scene) {
  nlohmann::json runs = nlohmann::json::array();
  for (const ModelRun& run : scene.runs) {
    runs.push_back(to_json(run));
  }
  nlohmann::json calibrations = nlohmann::json::object();
  for (const auto& [label, calibration] : scene.calibrations) {
    calibrations[label] = calibration;
  }
  return {{"name", scene.name},
          {"reference", scene.reference},
          {"runs", runs},
          {"calibrations", calibrations},
          {"notes", scene.notes}};
}

MatchedScene matched_from_json(const JsonReader& in) {
  MatchedScene scene;
  scene.name = in.string("name");
  scene.reference = in.string("reference");
  for (const JsonReader& run_in : in.objects("runs")) {
    scene.runs.push_back(model_run_from_json(run_in));
  }
  const nlohmann::json& calibrations = in.raw("calibrations");
  if (!calibrations.is_object()) {
    in.fail_expected("calibrations", "an object");
  }
  for (const auto& [label, calibration] : calibrations.items()) {
    scene.calibrations[label] = calibration;
  }
  const nlohmann::json& notes = in.raw("notes");
  if (!notes.is_array()) {
    in.fail_expected("notes", "an array of strings");
  }
  for (const nlohmann::json& note : notes) {
    if (!note.is_string()) {
      in.fail_expected("notes", "an array of strings");
    }
    scene.notes.push_back(note.get<std::string>());
  }
  return scene;
}

std::string setting_label(const SpeedSetting& setting) {
  std::string label = setting.settings.empty() ? "defaults" : setting.settings.dump();
  return label + ", dt " + fixed(setting.dt * 1000.0, 1) + " ms";
}

void equal_accuracy_table(std::ostream& out, const EqualAccuracy& trade) {
  out << "# C. Equal accuracy on " << trade.scene << "\n\n"
      << "For each error budget (RMS position error against the reference, relative to the "
         "reference's displacement), the fastest setting of each model within it, as simulated "
         "seconds per wall-clock second (step plus collision; above 1x is faster than real "
         "time). Every setting is matched to the tissue as in table B (a unitless model "
         "refitted at its setting and dt). \"-\": no setting tried is that accurate.\n\n";
  std::vector<std::string> models;
  for (const SpeedSetting& setting : trade.settings) {
    if (std::find(models.begin(), models.end(), setting.model) == models.end()) {
      models.push_back(setting.model);
    }
  }
  out << "| model |";
  for (double budget : trade.budgets) {
    out << " error <= " << fixed(100.0 * budget, 0) << "% |";
  }
  out << "\n|---|";
  for (std::size_t i = 0; i < trade.budgets.size(); ++i) {
    out << "---|";
  }
  out << "\n";
  for (const std::string& model : models) {
    out << "| " << model << " |";
    for (double budget : trade.budgets) {
      const std::optional<SpeedSetting> best = fastest_within(trade, model, budget);
      out << " "
          << (best ? fixed(best->realtime_factor, 2) + "x (" + setting_label(*best) + ")"
                   : std::string("-"))
          << " |";
    }
    out << "\n";
  }
  out << "\nEvery setting tried:\n\n| model | setting | real-time factor | error |\n"
         "|---|---|---|---|\n";
  for (const SpeedSetting& setting : trade.settings) {
    out << "| " << setting.model << " | " << setting_label(setting) << " | "
        << (setting.stable ? fixed(setting.realtime_factor, 2) + "x" : std::string("blew up"))
        << " | "
        << (setting.note.empty()
                ? (std::isfinite(setting.error) ? fixed(100.0 * setting.error, 1) + "%"
                                                : std::string("-"))
                : setting.note)
        << " |\n";
  }
  out << "\n";
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
  json["matched"] = nlohmann::json::array();
  for (const MatchedScene& scene : comparison.matched) {
    json["matched"].push_back(matched_json(scene));
  }
  json["equal_accuracy"] =
      comparison.equal_accuracy ? to_json(*comparison.equal_accuracy) : nlohmann::json(nullptr);
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
  for (const JsonReader& matched_in : root.objects("matched")) {
    comparison.matched.push_back(matched_from_json(matched_in));
  }
  if (!root.raw("equal_accuracy").is_null()) {
    try {
      comparison.equal_accuracy = equal_accuracy_from_json(root.raw("equal_accuracy"));
    } catch (const nlohmann::json::exception& error) {
      root.fail_expected("equal_accuracy", std::string("the equal-accuracy record (")
                                               + error.what() + ")");
    }
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
         "collision work (BVH refit, query, contact constraints), each the steps after warm-up "
         "over their summed time (a mean rate: the slow steps of a contact count in full, as a "
         "median would not let them), on "
      << comparison.machine
      << ". The thesis's: frames per second with rendering on an Intel Core i3-2100 @ 3.1 GHz, "
         "one step per frame, on its own liver mesh (section 3.5.1; its \"FEM\" figure stands "
         "beside both FEM rows). Residuals are RMS distances to the shape before the load, over "
         "the rest bounding-box diagonal, at the end of the run. The tool is the instrument, else "
         "the "
         "grasp; its force is the sum of the constraint forces the tissue exerts on it. "
         "\"warnings\" names the plausibility checks a run failed although it stayed stable "
         "(harness/run/plausibility.h); each is explained under its table.\n\n";
  if (!comparison.matched.empty()) {
    out << "# A. Thesis parameters\n\nThe literal reproduction: each model with the thesis's "
           "parameter values taken in SI units, so the rows are different materials (a "
           "mass-spring liver far stiffer than the FEM's, a shape-matching liver far softer).\n\n";
  }
  for (const SceneComparison& scene : comparison.scenes) {
    scene_table(out, scene);
  }
  if (!comparison.matched.empty()) {
    out << "# B. Matched to the tissue\n\nThe same scenes with every model made the same "
           "tissue: a model whose stiffness is not a material constant is calibrated "
           "(`softbench calibrate`) so that its static sag under gravity and its press forces at "
           "0.5, 1 and 2 cm past first contact match the reference's ("
        << comparison.matched.front().reference
        << ", on the scene's mesh, material and dt), and takes the reference's mass damping; "
           "the others follow the material as in table A. Each run is then measured against the "
           "converged reference (the same scene at a quarter of the dt): the RMS position error "
           "over 8 evenly spaced times, as a share of the rest bounding-box diagonal and of the "
           "reference's own displacement, and the error of the peak tool force. Real-time "
           "factor: simulated seconds per second of step plus collision. The thesis's claims are "
           "judged on this table.\n\n";
    for (std::size_t i = 0; i < comparison.matched.size(); ++i) {
      const double dt = i < comparison.scenes.size() && comparison.scenes[i].scene.contains("time")
                            ? comparison.scenes[i].scene["time"].value("dt", 0.0)
                            : 0.0;
      matched_table(out, comparison.matched[i], dt);
    }
  }
  if (comparison.equal_accuracy) {
    equal_accuracy_table(out, *comparison.equal_accuracy);
  }
  out << "## The thesis's claims (section 3.5.2)"
      << (comparison.matched.empty() ? "" : ", judged on table B") << "\n\n";
  for (const Claim& claim : comparison.claims) {
    out << claim_markdown(claim);
  }
  pictures_markdown(out, comparison);
  return out.str();
}

void write_comparison(const std::filesystem::path& out_dir, const Comparison& comparison) {
  write_report_files(out_dir, {{"compare.json", comparison_json(comparison).dump(1) + "\n"},
                               {"compare.md", comparison_markdown(comparison)}});
}

}  // namespace softbench::harness
