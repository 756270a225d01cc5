// SPDX-License-Identifier: MIT
#include "harness/compare/equal_accuracy.h"

#include "harness/format.h"
#include "geometry/input_error.h"
#include "harness/calibrate/calibration.h"
#include "harness/run/runner.h"
#include "models/model_registry.h"

#include <cmath>
#include <limits>

namespace softbench::harness {
namespace {


nlohmann::json finite_or_null(double value) {
  return std::isfinite(value) ? nlohmann::json(value) : nlohmann::json(nullptr);
}

SpeedSetting run_setting(const scenes::Scene& scene,
                         const SceneMesh& mesh,
                         const ReferenceRun& reference,
                         const std::string& model,
                         const nlohmann::json& settings,
                         int dt_factor,
                         const EqualAccuracyOptions& options) {
  SpeedSetting result;
  result.model = model;
  result.settings = settings;
  result.error = kInfinity;
  scenes::Scene variant = scene;
  variant.dt = scene.dt * dt_factor;
  result.dt = variant.dt;
  if (!settings.empty()) {
    variant.override_parameters(model, settings);
  }
  if (calibratable(model)) {
    // A unitless stiffness means something else at another dt or setting: refit it there.
    CalibrationOptions calibration;
    calibration.against = options.reference_model;
    calibration.cache_dir = options.calibration_dir;
    try {
      variant.model_parameters[model] = calibrate(variant, mesh, model, calibration).params;
    } catch (const InputError& error) {
      result.note = std::string("not calibrated: ") + error.what();
      return result;
    }
  }
  RunOptions run_options;
  run_options.models = {model};
  run_options.warmup_steps = options.warmup_steps;
  run_options.snapshot_times = reference.times;
  const ModelRun run = run_scene(variant, mesh, run_options).front();
  result.stable = run.stability.stable;
  if (result.stable) {
    result.realtime_factor = run.timing.steps_per_second_with_collision * variant.dt;
    result.error = accuracy_against(run.snapshots, run.contact.peak_tool_force, reference,
                                    mesh.body.rest_positions())
                       .rms_error;
  }
  if (options.progress != nullptr) {
    *options.progress << scene.name << " / " << model << " " << settings.dump() << " at dt "
                      << variant.dt << ": " << result.realtime_factor << "x real time, error "
                      << 100.0 * result.error << "%\n";
  }
  return result;
}

}  // namespace

EqualAccuracy run_equal_accuracy(const scenes::Scene& scene,
                                 const SceneMesh& mesh,
                                 const ReferenceRun& reference,
                                 const EqualAccuracyOptions& options) {
  EqualAccuracy trade;
  trade.scene = scene.name;
  for (const std::string& model : options.models) {
    std::vector<nlohmann::json> settings{nlohmann::json::object()};
    for (const nlohmann::json& setting : builtin_models().at(model).speed_settings) {
      settings.push_back(setting);
    }
    for (int factor : options.dt_factors) {
      for (const nlohmann::json& setting : settings) {
        trade.settings.push_back(
            run_setting(scene, mesh, reference, model, setting, factor, options));
      }
    }
  }
  return trade;
}

std::optional<SpeedSetting> fastest_within(const EqualAccuracy& trade,
                                           const std::string& model,
                                           double budget) {
  std::optional<SpeedSetting> best;
  for (const SpeedSetting& setting : trade.settings) {
    if (setting.model == model && setting.stable && setting.error <= budget
        && (!best || setting.realtime_factor > best->realtime_factor)) {
      best = setting;
    }
  }
  return best;
}

nlohmann::json to_json(const EqualAccuracy& trade) {
  nlohmann::json settings = nlohmann::json::array();
  for (const SpeedSetting& s : trade.settings) {
    settings.push_back({{"model", s.model},
                        {"settings", s.settings},
                        {"dt", s.dt},
                        {"stable", s.stable},
                        {"realtime_factor", s.realtime_factor},
                        {"error", finite_or_null(s.error)},
                        {"note", s.note}});
  }
  return {{"scene", trade.scene}, {"budgets", trade.budgets}, {"settings", settings}};
}

EqualAccuracy equal_accuracy_from_json(const nlohmann::json& json) {
  EqualAccuracy trade;
  trade.scene = json.at("scene").get<std::string>();
  trade.budgets = json.at("budgets").get<std::vector<double>>();
  for (const nlohmann::json& s : json.at("settings")) {
    SpeedSetting setting;
    setting.model = s.at("model").get<std::string>();
    setting.settings = s.at("settings");
    setting.dt = s.at("dt").get<double>();
    setting.stable = s.at("stable").get<bool>();
    setting.realtime_factor = s.at("realtime_factor").get<double>();
    setting.error = s.at("error").is_null() ? kInfinity : s.at("error").get<double>();
    setting.note = s.at("note").get<std::string>();
    trade.settings.push_back(std::move(setting));
  }
  return trade;
}

}  // namespace softbench::harness
