// SPDX-License-Identifier: MIT
// The converged reference a scene's runs are measured against: the scene run through the
// reference model (the hyperelastic neo_hookean by default) with a smaller time step, its shape
// kept at a few fixed times. Cached on disk under a hash of the scene and these settings, so a
// sweep, a re-run or another shard computes it once.
#pragma once

#include "scenes/scene.h"

#include <Eigen/Core>
#include <nlohmann/json.hpp>

#include <filesystem>
#include <string>
#include <vector>

namespace softbench::harness {

struct ReferenceSettings {
  std::string model = "neo_hookean";
  /// The reference's dt is the scene's dt / substeps. 4 relies on the scene damping its motion
  /// (the shipped press and pull scenes do); an undamped sag needs 8 at 1/60 s (see
  /// models/neo_hookean/neo_hookean.h for the measured convergence).
  int substeps = 4;
  int times = 8;  ///< compared at this many evenly spaced times in (0, duration]
};

struct ReferenceRun {
  nlohmann::json settings;                  ///< what was run (scene, model, dt), for the record
  std::vector<double> times;                ///< s
  std::vector<Eigen::Matrix3Xd> positions;  ///< 3 x #V at each time
  std::vector<double> volumes;              ///< m^3 at each time
  double peak_tool_force = 0.0;             ///< N
};

/// FNV-1a 64 of `text` as 16 hex digits: a name that is the same on every machine.
std::string stable_hash(const std::string& text);

/// The compared times for `scene`: `count` evenly spaced in (0, duration].
std::vector<double> comparison_times(const scenes::Scene& scene, int count);

/// The reference for `scene`, from cache_dir/<hash>.json if there, else run (and cached).
/// Throws InputError if the reference model is not registered or the run blows up.
ReferenceRun reference_run(const scenes::Scene& scene,
                           const ReferenceSettings& settings,
                           const std::filesystem::path& cache_dir);

}  // namespace softbench::harness
