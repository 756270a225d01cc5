// SPDX-License-Identifier: MIT
// The speed-accuracy trade as one table and one picture: each model run at its cheaper settings
// (ModelInfo::speed_settings) and a doubled time step, every run matched to the tissue as in
// table B and measured against the converged reference; for each error budget, the fastest
// setting of each model that stays within it, in simulated seconds per wall-clock second.
#pragma once

#include "harness/run/accuracy.h"
#include "harness/run/scene_mesh.h"
#include "scenes/scene.h"

#include <nlohmann/json.hpp>

#include <filesystem>
#include <optional>
#include <ostream>
#include <string>
#include <vector>

namespace softbench::harness {

/// One model at one setting.
struct SpeedSetting {
  std::string model;
  nlohmann::json settings;  ///< the overrides over the scene's block ({} for its defaults)
  double dt = 0.0;          ///< s
  bool stable = false;
  /// Simulated seconds per wall-clock second of step plus collision (steps/s with collision x
  /// dt); 0 when it blew up.
  double realtime_factor = 0.0;
  /// RMS position error against the reference over its compared times, relative to the
  /// reference's displacement (Accuracy::rms_error); infinite when it blew up.
  double error = 0.0;
  std::string note;  ///< why it was not run ("" when it was)
};

struct EqualAccuracy {
  std::string scene;
  std::vector<double> budgets{0.05, 0.10, 0.20, 0.40};
  std::vector<SpeedSetting> settings;
};

struct EqualAccuracyOptions {
  std::vector<std::string> models;  ///< registered models (no variants)
  std::vector<int> dt_factors{1, 2};
  std::filesystem::path calibration_dir = std::filesystem::path("out") / "calibration";
  std::string reference_model = "neo_hookean";
  int warmup_steps = 10;
  std::ostream* progress = nullptr;
};

/// Runs every model at every setting on `scene` against `reference` (reference_run's, with
/// its times). A setting whose calibration fails is kept with a note, not run.
EqualAccuracy run_equal_accuracy(const scenes::Scene& scene,
                                 const SceneMesh& mesh,
                                 const ReferenceRun& reference,
                                 const EqualAccuracyOptions& options);

/// The fastest of `model`'s stable settings with an error within `budget`, if any.
std::optional<SpeedSetting> fastest_within(const EqualAccuracy& trade,
                                           const std::string& model,
                                           double budget);

nlohmann::json to_json(const EqualAccuracy& trade);
EqualAccuracy equal_accuracy_from_json(const nlohmann::json& json);

}  // namespace softbench::harness
