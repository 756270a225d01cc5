// SPDX-License-Identifier: MIT
#include "harness/report/model_run_json.h"

#include "harness/format.h"

#include <cmath>
#include <limits>

namespace softbench::harness {
namespace {

constexpr int kMaxCount = std::numeric_limits<int>::max();

nlohmann::json optional_json(const std::optional<double>& value) {
  return value ? number_or_null(*value) : nlohmann::json(nullptr);
}

// A number written by number_or_null: null reads back as `if_null`.
double number_or(const JsonReader& in, std::string_view key, double if_null) {
  return in.raw(key).is_null() ? if_null : in.number(key);
}

std::optional<double> optional_number(const JsonReader& in, std::string_view key) {
  return in.raw(key).is_null() ? std::nullopt : std::optional<double>(in.number(key));
}

nlohmann::json percentiles_json(const Percentiles& p) {
  return {{"median", p.median}, {"p95", p.p95}, {"max", p.max}};
}

Percentiles read_percentiles(const JsonReader& in) {
  return {in.number("median"), in.number("p95"), in.number("max")};
}

nlohmann::json series_json(const std::vector<StepSample>& samples) {
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

// One column of the series: numbers, null read back as NaN.
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

std::vector<StepSample> read_series(const JsonReader& in) {
  const std::vector<double> time = read_column(in, "time");
  const std::vector<double> displacement = read_column(in, "tool_displacement");
  const std::vector<double> force = read_column(in, "tool_force");
  const std::vector<double> residual = read_column(in, "recovery_residual");
  if (displacement.size() != time.size() || force.size() != time.size()
      || residual.size() != time.size()) {
    in.fail("time", "the series columns differ in length");
  }
  std::vector<StepSample> samples(time.size());
  for (std::size_t i = 0; i < time.size(); ++i) {
    samples[i] = {time[i], displacement[i], force[i], residual[i]};
  }
  return samples;
}

}  // namespace

nlohmann::json to_json(const ModelRun& run) {
  nlohmann::json json;
  json["model"] = run.model;
  json["params"] = run.params;
  json["mesh"] = {{"vertices", run.vertices}, {"tets", run.tets}};
  const TimingMetrics& timing = run.timing;
  json["timing"] = {{"steps_planned", timing.steps_planned},
                    {"steps_run", timing.steps_run},
                    {"interrupted", timing.interrupted},
                    {"step_ms", percentiles_json(timing.step_ms)},
                    {"steps_per_second", timing.steps_per_second},
                    {"step_with_collision_ms", percentiles_json(timing.step_with_collision_ms)},
                    {"steps_per_second_with_collision", timing.steps_per_second_with_collision}};
  const StabilityMetrics& stability = run.stability;
  json["stability"] = {
      {"stable", stability.stable},
      {"diverged_at_step", stability.diverged_at_step ? nlohmann::json(*stability.diverged_at_step)
                                                      : nlohmann::json(nullptr)},
      {"divergence", stability.divergence},
      {"max_speed", number_or_null(stability.max_speed)},
      {"max_kinetic_energy", number_or_null(stability.max_kinetic_energy)}};
  json["shape"] = {{"max_inverted_tets", run.shape.max_inverted_tets},
                   {"final_inverted_tets", run.shape.final_inverted_tets},
                   {"volume_change", number_or_null(run.shape.volume_change)},
                   {"final_elastic_energy", number_or_null(run.shape.final_elastic_energy)}};
  if (run.recovery.measured) {
    json["recovery"] = {{"residual", number_or_null(run.recovery.residual)},
                        {"time_to_one_percent_s", optional_json(run.recovery.time_to_one_percent)}};
  } else {
    json["recovery"] = nullptr;  // nothing was released, or the run diverged
  }
  const ContactMetrics& contact = run.contact;
  json["contact"] = {{"max_penetration", contact.max_penetration},
                     {"max_penetration_pressing", contact.max_penetration_pressing},
                     {"lost_contact_vertices", contact.lost_contact_vertices},
                     {"max_triangle_pairs", contact.max_triangle_pairs},
                     {"peak_tool_force", contact.peak_tool_force},
                     {"loaded_travel", contact.loaded_travel},
                     {"unsettled_steps", contact.unsettled_steps}};
  const SolverMetrics& solver = run.solver;
  json["solver"] = {{"mean_iterations", solver.mean_iterations},
                    {"factorizations", solver.factorizations},
                    {"linear_solves", solver.linear_solves},
                    {"truncated_solves", solver.truncated_solves},
                    {"max_constraint_error", solver.max_constraint_error},
                    {"final_reaction_sum",
                     {number_or_null(solver.final_reaction_sum.x()),
                      number_or_null(solver.final_reaction_sum.y()),
                      number_or_null(solver.final_reaction_sum.z())}},
                    {"memory_bytes", solver.memory_bytes}};
  if (run.accuracy) {
    const Accuracy& a = *run.accuracy;
    json["accuracy"] = {{"rms_error", number_or_null(a.rms_error)},
                        {"max_error", number_or_null(a.max_error)},
                        {"volume_error", number_or_null(a.volume_error)},
                        {"peak_force_error", optional_json(a.peak_force_error)},
                        {"diagonal_error", number_or_null(a.diagonal_error)}};
  } else {
    json["accuracy"] = nullptr;  // the scene asks for no accuracy: no reference was run
  }
  json["warnings"] = nlohmann::json::array();
  for (const Warning& warning : run.warnings) {
    json["warnings"].push_back({{"id", warning.id}, {"message", warning.message}});
  }
  json["series"] = series_json(run.samples);
  return json;
}

ModelRun model_run_from_json(const JsonReader& in) {
  ModelRun run;
  run.model = in.string("model");
  run.params = in.raw("params");
  const JsonReader mesh = in.object("mesh");
  run.vertices = mesh.integer("vertices", 0, kMaxCount);
  run.tets = mesh.integer("tets", 0, kMaxCount);

  const JsonReader timing = in.object("timing");
  run.timing.steps_planned = timing.integer("steps_planned", 0, kMaxCount);
  run.timing.steps_run = timing.integer("steps_run", 0, kMaxCount);
  run.timing.interrupted = timing.boolean_or("interrupted", false);
  run.timing.step_ms = read_percentiles(timing.object("step_ms"));
  run.timing.steps_per_second = timing.number("steps_per_second");
  run.timing.step_with_collision_ms = read_percentiles(timing.object("step_with_collision_ms"));
  run.timing.steps_per_second_with_collision = timing.number("steps_per_second_with_collision");

  const JsonReader stability = in.object("stability");
  run.stability.stable = stability.boolean_or("stable", true);
  if (!stability.raw("diverged_at_step").is_null()) {
    run.stability.diverged_at_step = stability.integer("diverged_at_step", 0, kMaxCount);
  }
  run.stability.divergence = stability.string("divergence");
  run.stability.max_speed = number_or(stability, "max_speed", kInfinity);
  run.stability.max_kinetic_energy = number_or(stability, "max_kinetic_energy", kInfinity);

  const JsonReader shape = in.object("shape");
  run.shape.max_inverted_tets = shape.integer("max_inverted_tets", 0, kMaxCount);
  run.shape.final_inverted_tets = shape.integer("final_inverted_tets", 0, kMaxCount);
  run.shape.volume_change = number_or(shape, "volume_change", kInfinity);
  run.shape.final_elastic_energy = number_or(shape, "final_elastic_energy", kNaN);

  run.recovery.measured = !in.raw("recovery").is_null();
  if (run.recovery.measured) {
    const JsonReader recovery = in.object("recovery");
    run.recovery.residual = number_or(recovery, "residual", kInfinity);
    run.recovery.time_to_one_percent = optional_number(recovery, "time_to_one_percent_s");
  }

  const JsonReader contact = in.object("contact");
  run.contact.max_penetration = contact.number("max_penetration");
  run.contact.max_penetration_pressing = contact.number("max_penetration_pressing");
  run.contact.lost_contact_vertices = contact.integer("lost_contact_vertices", 0, kMaxCount);
  run.contact.max_triangle_pairs = contact.integer("max_triangle_pairs", 0, kMaxCount);
  run.contact.peak_tool_force = contact.number("peak_tool_force");
  run.contact.loaded_travel = contact.number("loaded_travel");
  run.contact.unsettled_steps = contact.integer("unsettled_steps", 0, kMaxCount);

  const JsonReader solver = in.object("solver");
  run.solver.mean_iterations = solver.number("mean_iterations");
  run.solver.factorizations = solver.integer("factorizations", 0, kMaxCount);
  run.solver.linear_solves = solver.integer("linear_solves", 0, kMaxCount);
  run.solver.truncated_solves = solver.integer("truncated_solves", 0, kMaxCount);
  run.solver.max_constraint_error = solver.number("max_constraint_error");
  const nlohmann::json& reactions = solver.raw("final_reaction_sum");
  if (!reactions.is_array() || reactions.size() != 3) {
    solver.fail_expected("final_reaction_sum", "[x, y, z] (null for NaN)");
  }
  for (int i = 0; i < 3; ++i) {
    const nlohmann::json& value = reactions[static_cast<std::size_t>(i)];
    run.solver.final_reaction_sum[i] = value.is_number() ? value.get<double>() : kNaN;
  }
  const nlohmann::json& memory = solver.raw("memory_bytes");
  if (!memory.is_number_unsigned()) {
    solver.fail_expected("memory_bytes", "a byte count");
  }
  run.solver.memory_bytes = memory.get<std::size_t>();

  if (!in.raw("accuracy").is_null()) {
    const JsonReader accuracy = in.object("accuracy");
    run.accuracy = Accuracy{number_or(accuracy, "rms_error", kInfinity),
                            number_or(accuracy, "max_error", kInfinity),
                            number_or(accuracy, "volume_error", kInfinity),
                            optional_number(accuracy, "peak_force_error"),
                            number_or(accuracy, "diagonal_error", kInfinity)};
  }
  for (const JsonReader& warning : in.objects("warnings")) {
    run.warnings.push_back({warning.string("id"), warning.string("message")});
    warning.reject_unknown_keys();
  }
  run.samples = read_series(in.object("series"));
  return run;
}

}  // namespace softbench::harness
