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

/// The accuracy a reference must have converged to when the scene states none
/// (Requirements::accuracy): the finest error budget a sweep ranks models at.
inline constexpr double kDefaultReferenceBudget = 0.01;

/// Whether a reference has converged: the same scene at twice its substeps, compared at its
/// times by the measure models are ranked by (Accuracy::rms_error). On an undamped scene the
/// two differ by the phase of an oscillation that neither time step resolves, and every model's
/// "error" against either is that phase, not the model's: a sweep does not rank models on it.
struct ReferenceConvergence {
  /// False when the sweep was told to trust the reference (nothing was run to check it).
  bool checked = false;
  int substeps = 0;         ///< the reference's
  int finer_substeps = 0;   ///< the run it was compared with
  double difference = 0.0;  ///< the reference's rms_error against the finer run
  double budget = kDefaultReferenceBudget;  ///< the scene's accuracy requirement, or the default
  bool budget_from_scene = false;           ///< the scene states it (Requirements::accuracy)
  bool converged() const { return difference <= budget; }
};

/// Runs (or reads from cache_dir) the finer reference and compares `reference` with it.
ReferenceConvergence reference_convergence(const scenes::Scene& scene,
                                           const SceneMesh& mesh,
                                           const ReferenceSettings& settings,
                                           const std::filesystem::path& cache_dir,
                                           const ReferenceRun& reference);

/// Why models are not ranked against a reference that did not converge; empty when they are
/// (converged, or trusted unchecked).
std::string ranking_refusal(const ReferenceConvergence& convergence);

nlohmann::json to_json(const ReferenceConvergence& convergence);
ReferenceConvergence reference_convergence_from_json(const nlohmann::json& json,
                                                     const std::string& where);

}  // namespace softbench::harness
