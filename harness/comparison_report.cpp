// SPDX-License-Identifier: MIT
#include "harness/comparison_report.h"

#include "geometry/atomic_file.h"
#include "geometry/input_error.h"
#include "harness/report.h"
#include "models/json_reader.h"

#include <cmath>
#include <iomanip>
#include <limits>
#include <sstream>

namespace softbench::harness {
namespace {

constexpr const char* kSource = "compare.json";

nlohmann::json percentiles_json(const Percentiles& p) {
  return {{"median", p.median}, {"p95", p.p95}, {"max", p.max}};
}

Percentiles read_percentiles(const JsonReader& in) {
  return {in.number("median"), in.number("p95"), in.number("max")};
}

nlohmann::json samples_json(const std::vector<StepSample>& samples) {
  nlohmann::json time = nlohmann::json::array();
  nlohmann::json displacement = nlohmann::json::array();
  nlohmann::json force = nlohmann::json::array();
  nlohmann::json residual = nlohmann::json::array();
  for (const StepSample& sample : samples) {
    time.push_back(sample.time);
    displacement.push_back(number_or_null(sample.tool_displacement));
    force.push_back(number_or_null(sample.tool_force));
    residual.push_back(number_or_null(sample.recovery_residual));
  }
  return {{"time", time},
          {"tool_displacement", displacement},
          {"tool_force", force},
          {"recovery_residual", residual}};
}

// One column of samples: numbers, null read back as NaN.
std::vector<double> read_column(const JsonReader& in, std::string_view key) {
  const nlohmann::json& column = in.raw(key);
  if (!column.is_array()) {
    in.fail_expected(key, "an array of numbers (null for NaN)");
  }
  std::vector<double> values;
  values.reserve(column.size());
  for (const nlohmann::json& value : column) {
    if (value.is_null()) {
      values.push_back(std::numeric_limits<double>::quiet_NaN());
    } else if (value.is_number()) {
      values.push_back(value.get<double>());
    } else {
      in.fail_expected(key, "an array of numbers (null for NaN)");
    }
  }
  return values;
}

std::vector<StepSample> read_samples(const JsonReader& in) {
  const std::vector<double> time = read_column(in, "time");
  const std::vector<double> displacement = read_column(in, "tool_displacement");
  const std::vector<double> force = read_column(in, "tool_force");
  const std::vector<double> residual = read_column(in, "recovery_residual");
  if (displacement.size() != time.size() || force.size() != time.size()
      || residual.size() != time.size()) {
    in.fail("time", "the sample columns differ in length");
  }
  std::vector<StepSample> samples(time.size());
  for (std::size_t i = 0; i < time.size(); ++i) {
    samples[i] = {time[i], displacement[i], force[i], residual[i]};
  }
  return samples;
}

nlohmann::json run_json(const ModelRun& run) {
  nlohmann::json json;
  json["model"] = run.model;
  const std::optional<double> thesis = thesis_steps_per_second(run.model);
  json["thesis_steps_per_second"] = thesis ? nlohmann::json(*thesis) : nlohmann::json(nullptr);
  json["params"] = run.params;
  json["mesh"] = {{"vertices", run.vertices}, {"tets", run.tets}};
  json["steps"] = run.steps_run;
  json["steps_planned"] = run.steps_planned;
  json["step_ms"] = percentiles_json(run.step_ms);
  json["fps"] = run.fps;
  json["step_with_collision_ms"] = percentiles_json(run.step_with_collision_ms);
  json["fps_with_collision"] = run.fps_with_collision;
  json["stable"] = run.stable;
  json["diverged_at_step"] =
      run.diverged_at_step ? nlohmann::json(*run.diverged_at_step) : nlohmann::json(nullptr);
  json["divergence"] = run.divergence;
  json["max_inverted_tets"] = run.max_inverted_tets;
  json["volume_change"] = run.volume_change;
  json["max_speed"] = number_or_null(run.max_speed);
  if (run.recovery_measured) {
    json["recovery"] = {{"residual_rms_rel", run.recovery_residual},
                        {"time_to_1pct_s", run.time_to_1pct ? nlohmann::json(*run.time_to_1pct)
                                                            : nlohmann::json(nullptr)}};
  } else {
    json["recovery"] = nullptr;
  }
  json["max_penetration"] = run.max_penetration;
  json["lost_contact_vertices"] = run.lost_contact_vertices;
  json["peak_tool_force"] = run.peak_tool_force;
  json["mean_iterations"] = run.mean_iterations;
  json["samples"] = samples_json(run.samples);
  return json;
}

ModelRun read_run(const JsonReader& in) {
  ModelRun run;
  run.model = in.string("model");
  run.params = in.raw("params");
  const JsonReader mesh = in.object("mesh");
  run.vertices = mesh.integer("vertices", 0, std::numeric_limits<int>::max());
  run.tets = mesh.integer("tets", 0, std::numeric_limits<int>::max());
  run.steps_run = in.integer("steps", 0, std::numeric_limits<int>::max());
  run.steps_planned = in.integer("steps_planned", 0, std::numeric_limits<int>::max());
  run.step_ms = read_percentiles(in.object("step_ms"));
  run.fps = in.number("fps");
  run.step_with_collision_ms = read_percentiles(in.object("step_with_collision_ms"));
  run.fps_with_collision = in.number("fps_with_collision");
  run.stable = in.boolean_or("stable", true);
  if (!in.raw("diverged_at_step").is_null()) {
    run.diverged_at_step = in.integer("diverged_at_step", 0, std::numeric_limits<int>::max());
  }
  run.divergence = in.string("divergence");
  run.max_inverted_tets = in.integer("max_inverted_tets", 0, std::numeric_limits<int>::max());
  run.volume_change = in.number("volume_change");
  run.max_speed = in.raw("max_speed").is_null() ? std::numeric_limits<double>::infinity()
                                                : in.number("max_speed");
  run.recovery_measured = !in.raw("recovery").is_null();
  if (run.recovery_measured) {
    const JsonReader recovery = in.object("recovery");
    run.recovery_residual = recovery.number("residual_rms_rel");
    if (!recovery.raw("time_to_1pct_s").is_null()) {
      run.time_to_1pct = recovery.number("time_to_1pct_s");
    }
  }
  run.max_penetration = in.number("max_penetration");
  run.lost_contact_vertices =
      in.integer("lost_contact_vertices", 0, std::numeric_limits<int>::max());
  run.peak_tool_force = in.number("peak_tool_force");
  run.mean_iterations = in.number("mean_iterations");
  run.samples = read_samples(in.object("samples"));
  return run;
}

// Steps per second to three significant figures at least, without a pointless fraction.
std::string rate(double value) {
  if (!(value > 0.0)) {
    return "-";
  }
  return fixed(value, value >= 100.0 ? 0 : 1);
}

std::string verdict_badge(Verdict verdict) {
  switch (verdict) {
    case Verdict::kPass:
      return "**PASS**";
    case Verdict::kFail:
      return "**FAIL**";
    case Verdict::kObserved:
      return "**OBSERVED**";
    case Verdict::kNotObserved:
      return "**NOT OBSERVED**";
    case Verdict::kNotRun:
      return "**NOT RUN**";
  }
  return "";
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
         "| max volume change |\n";
  out << "|---|---|---|---|---|---|---|---|---|---|---|\n";
  for (const ModelRun& run : scene.runs) {
    const std::optional<double> thesis = thesis_steps_per_second(run.model);
    out << "| " << run.model << " | " << (thesis ? fixed(*thesis, 1) : "-") << " | "
        << rate(run.fps) << " | " << rate(run.fps_with_collision) << " | "
        << (run.stable
                ? "yes"
                : "NO (step " + (run.diverged_at_step ? std::to_string(*run.diverged_at_step) : "?")
                      + ": " + run.divergence + ")")
        << " | " << run.max_inverted_tets << " | "
        << (run.recovery_measured ? fixed(100.0 * run.recovery_residual, 2) + "%" : "-") << " | "
        << (run.time_to_1pct ? fixed(*run.time_to_1pct, 2) : "-") << " | "
        << fixed(1000.0 * run.max_penetration, 2) << " | " << fixed(run.peak_tool_force, 3) << " | "
        << fixed(100.0 * run.volume_change, 2) << "% |\n";
  }
  out << "\n";
}

}  // namespace

nlohmann::json comparison_json(const Comparison& comparison) {
  nlohmann::json json;
  json["softbench_compare"] = kCompareSchemaVersion;
  json["machine"] = comparison.machine;
  json["thesis"] = {
      {"hardware", "Intel Core i3-2100 @ 3.1 GHz, NVIDIA GeForce GTS450, 6 GB (thesis 3.5)"},
      {"note", "frames per second with rendering, one simulation step per frame"},
      {"steps_per_second",
       {{"mass_spring", *thesis_steps_per_second("mass_spring")},
        {"fem", *thesis_steps_per_second("corotational_fem")},
        {"shape_matching", *thesis_steps_per_second("shape_matching")}}}};
  json["criteria"] = {{"recovery_residual", comparison.criteria.recovery_residual},
                      {"max_inverted_tets", comparison.criteria.max_inverted_tets},
                      {"volume_ratio", comparison.criteria.volume_ratio},
                      {"volume_margin", comparison.criteria.volume_margin}};
  json["scenes"] = nlohmann::json::array();
  for (const SceneComparison& scene : comparison.scenes) {
    nlohmann::json runs = nlohmann::json::array();
    for (const ModelRun& run : scene.runs) {
      runs.push_back(run_json(run));
    }
    json["scenes"].push_back({{"name", scene.name}, {"scene", scene.scene}, {"runs", runs}});
  }
  json["claims"] = nlohmann::json::array();
  for (const ClaimCheck& claim : comparison.claims) {
    json["claims"].push_back({{"id", claim.id},
                              {"claim", claim.claim},
                              {"criterion", claim.criterion},
                              {"verdict", to_string(claim.verdict)},
                              {"evidence", claim.evidence}});
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
  comparison.criteria.recovery_residual = criteria.number("recovery_residual");
  comparison.criteria.max_inverted_tets =
      criteria.integer("max_inverted_tets", 0, std::numeric_limits<int>::max());
  comparison.criteria.volume_ratio = criteria.number("volume_ratio");
  comparison.criteria.volume_margin = criteria.number("volume_margin");
  for (const JsonReader& scene_in : root.objects("scenes")) {
    SceneComparison scene;
    scene.name = scene_in.string("name");
    scene.scene = scene_in.raw("scene");
    for (const JsonReader& run_in : scene_in.objects("runs")) {
      scene.runs.push_back(read_run(run_in));
    }
    comparison.scenes.push_back(std::move(scene));
  }
  for (const JsonReader& claim_in : root.objects("claims")) {
    ClaimCheck claim;
    claim.id = claim_in.string("id");
    claim.claim = claim_in.string("claim");
    claim.criterion = claim_in.string("criterion");
    try {
      claim.verdict = verdict_from_string(claim_in.string("verdict"));
    } catch (const InputError& error) {
      claim_in.fail("verdict", error.what());
    }
    claim.evidence = claim_in.string("evidence");
    comparison.claims.push_back(std::move(claim));
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
         "grasp; its force is the sum of the constraint forces the tissue exerts on it.\n\n";
  for (const SceneComparison& scene : comparison.scenes) {
    scene_table(out, scene);
  }
  out << "## The thesis's claims (section 3.5.2)\n\n";
  for (const ClaimCheck& claim : comparison.claims) {
    out << "- " << verdict_badge(claim.verdict) << " " << claim.claim << "\n"
        << "  - criterion: " << claim.criterion << "\n"
        << "  - evidence: " << claim.evidence << "\n";
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
