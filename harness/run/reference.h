// SPDX-License-Identifier: MIT
// The converged reference a scene's runs are measured against: the scene run through the
// reference model (the hyperelastic neo_hookean by default) with a smaller time step, its shape
// kept at a few fixed times. Cached on disk under a hash of the scene, the mesh's content, these
// settings and the build, so a sweep, a re-run or another shard computes it once, and a cache
// from another mesh or build is never read as this one's.
#pragma once

#include "harness/run/accuracy.h"
#include "harness/run/scene_mesh.h"
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

/// The reference for `scene`, from cache_dir/<hash>.json if there, else run (and cached).
/// Throws InputError if the reference model is not registered or the run blows up.
ReferenceRun reference_run(const scenes::Scene& scene,
                           const SceneMesh& mesh,
                           const ReferenceSettings& settings,
                           const std::filesystem::path& cache_dir);

}  // namespace softbench::harness
