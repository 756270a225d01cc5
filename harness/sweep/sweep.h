// SPDX-License-Identifier: MIT
// The speed-accuracy sweep: a grid of model settings run on one scene, each run timed and
// compared with a converged reference run of the same scene at fixed times. Runs are stored one
// file each, named by a hash of what they ran, so a sweep resumes where it stopped and can be
// split across machines (--shard i/N) and merged.
#pragma once

#include "harness/run/accuracy.h"
#include "harness/run/reference.h"
#include "harness/run/runner.h"
#include "scenes/scene.h"

#include <nlohmann/json.hpp>

#include <filesystem>
#include <optional>
#include <string>
#include <vector>

namespace softbench::harness {

/// One axis of the grid: `model.key=v1,v2,...`. `model` is a model name, or "model" for every
/// model; `key` is a model parameter, or "dt" for the scene's time step.
struct SweepAxis {
  std::string model;
  std::string key;
  std::vector<nlohmann::json> values;
};

/// Parses `model.key=v1,v2,...`; values are numbers (fractions such as 1/60 allowed), true,
/// false, or strings. Throws InputError naming the argument.
SweepAxis parse_sweep_axis(const std::string& argument);

/// One point of the grid: a model, the scene's dt, and parameter overrides.
struct SweepPoint {
  std::string model;
  double dt = 0.0;          ///< s
  nlohmann::json settings;  ///< the overridden parameters (object; "dt" included)
  /// Stable hash of scene, mesh content, build, model and settings: the run's file name, so
  /// shards of two meshes or two builds never merge as one run.
  std::string id;
};

/// Every point, in a deterministic order: per model (`models` when given, else every model a
/// run runs by default, less the reference model; a model without a block in the scene runs
/// with its defaults), the product of the axes that apply. `mesh_hash`: SceneMesh::content_hash.
std::vector<SweepPoint> sweep_grid(const scenes::Scene& scene,
                                   const std::string& mesh_hash,
                                   const std::vector<SweepAxis>& axes,
                                   const std::vector<std::string>& models,
                                   const std::string& reference_model);

struct SweepRecord {
  SweepPoint point;
  bool stable = true;
  double steps_per_second = 0.0;  ///< with collision where the scene has an instrument
  Accuracy accuracy;
  nlohmann::json provenance;  ///< the build and machine that ran it (null in older records)
};

nlohmann::json to_json(const SweepRecord& record);
SweepRecord sweep_record_from_json(const nlohmann::json& json, const std::string& where);

/// Stores `record` as out_dir/runs/<id>.json (atomically): one file per run is what lets a
/// sweep resume and shards merge.
void write_sweep_record(const std::filesystem::path& out_dir, const SweepRecord& record);

struct SweepOptions {
  std::vector<SweepAxis> axes;
  std::vector<std::string> models;  ///< empty: the scene's model blocks
  int shard = 0;                    ///< this machine runs the points with index % shards == shard
  int shards = 1;
  std::filesystem::path out_dir;  ///< runs/<id>.json, reference/, sweep.json, sweep.csv
  ReferenceSettings reference;
  /// Where the reference (and the finer run that checks it) is cached; empty: out_dir/reference.
  /// Shards given one shared folder, filled before they start, compute it once between them.
  std::filesystem::path reference_dir;
  /// Rank models on the reference without checking that it converged (ReferenceConvergence).
  bool trust_reference = false;
  /// Compute the reference and its check only, no model runs: what a cluster runs once
  /// before the shards.
  bool reference_only = false;
  std::ostream* progress = nullptr;
};

/// The file in a sweep's folder that records the reference's convergence check.
inline constexpr const char* kReferenceConvergenceFile = "reference_convergence.json";

/// What run_sweep found: every record of its runs folder and the reference's convergence check.
struct SweepResult {
  std::vector<SweepRecord> records;
  ReferenceConvergence convergence;
};

/// Computes or reads the reference, checks its convergence (unless trusted; recorded in
/// out_dir/kReferenceConvergenceFile), then runs the points of this shard that have no file yet
/// under out_dir/runs. Returns every record found there (none with reference_only) and the check.
SweepResult run_sweep(const scenes::Scene& scene, const SweepOptions& options);

/// The records of one or more runs folders (sweep output dirs), deduplicated by id.
std::vector<SweepRecord> read_sweep_runs(const std::vector<std::filesystem::path>& dirs);

/// Records `convergence` in dir/kReferenceConvergenceFile (atomically).
void write_reference_convergence(const std::filesystem::path& dir,
                                 const ReferenceConvergence& convergence);
/// The reference's convergence check of the first of `dirs` that has one (shards share one
/// reference); unchecked when none has (a sweep from before the check).
ReferenceConvergence read_reference_convergence(const std::vector<std::filesystem::path>& dirs);

/// Per model, the runs no other run of that model beats on both speed and rms_error.
std::vector<SweepRecord> pareto_front(const std::vector<SweepRecord>& records);

/// sweep.json (records, the reference's convergence, Pareto front, per error budget the fastest
/// run) and sweep.csv; the sweep command draws sweep.png from sweep.json with
/// tools/plot_sweep.py. Against a reference that did not converge (ranking_refusal) the front
/// and the budgets are empty and sweep.json says why.
void write_sweep_table(const std::filesystem::path& out_dir,
                       const std::string& scene_name,
                       const std::vector<SweepRecord>& records,
                       const ReferenceConvergence& convergence);

/// The fastest stable record whose rms_error is within `budget` (relative), if any.
std::optional<SweepRecord> fastest_within(const std::vector<SweepRecord>& records, double budget);

}  // namespace softbench::harness
