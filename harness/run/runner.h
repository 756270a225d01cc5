// SPDX-License-Identifier: MIT
#pragma once

#include "harness/run/accuracy.h"
#include "harness/run/metrics.h"
#include "harness/run/scene_mesh.h"
#include "scenes/scene.h"

#include <nlohmann/json.hpp>

#include <cstddef>
#include <filesystem>
#include <limits>
#include <optional>
#include <ostream>
#include <string>
#include <vector>

namespace softbench::harness {

struct RunOptions {
  std::vector<std::string> models;   ///< empty: every registered model
  int warmup_steps = 10;             ///< steps run but left out of the timing statistics
  int frames_every = 0;              ///< write a .vtu frame every N steps (0: none)
  std::filesystem::path frames_dir;  ///< where frames go (frames_dir/<model>/frame_NNNNN.vtu)
  std::ostream* progress = nullptr;  ///< one line per model when it finishes
  bool live_progress = false;        ///< also rewrite a step counter line (for a terminal)
  /// s: scene times at which to keep the body's positions (ModelRun::snapshots), e.g. to compare
  /// against a reference run; each is taken at the end of the first step ending at or after it.
  std::vector<double> snapshot_times;
  /// s, increasing: also captured, as snapshot_times are, into ModelRun::pictures (drawn by the
  /// reports, compared with nothing; picture_times() gives a scene's).
  std::vector<double> picture_times;
  /// On a stop asked for (Ctrl-C, SIGTERM): false, run_scene throws Interrupted and nothing of
  /// the unfinished run is kept; true, the model's run ends after the current step, is returned
  /// with TimingMetrics::interrupted set (its measures cover the steps run), and no further
  /// model runs. Only a command that writes each run as it is (softbench run) keeps it: one that
  /// compares or fits runs would take a part for the whole.
  bool keep_interrupted = false;
};

/// How many values of each per-step series (StepSample, step times) a run keeps: every step of
/// a run up to this many, an even thinning of a longer one (DecimatedSeries), so that memory
/// and metrics.json stay bounded whatever the scene's duration.
inline constexpr std::size_t kSeriesCapacity = std::size_t{1} << 16;

/// One step of a run, recorded for the curves (force-displacement, recovery over time).
struct StepSample {
  double time = 0.0;  ///< s, scene time at the end of the step
  /// m: how far the tool that loads the tissue (the instrument, else the grasp) has moved from
  /// where it started; 0 before it acts.
  double tool_displacement = 0.0;
  double tool_force = 0.0;  ///< N: |sum of the constraint forces the tissue exerts on the tool|
  /// Recovery residual (RMS distance to the reference shape / rest bbox diagonal); NaN before
  /// the release.
  double recovery_residual = std::numeric_limits<double>::quiet_NaN();
};

/// How long the steps took. Timed around step() alone, and around step() plus the step's
/// collision work (BVH refit, query, contact constraints: equal to the first without an
/// instrument); warm-up steps excluded.
struct TimingMetrics {
  int steps_planned = 0;
  int steps_run = 0;
  /// Stopped by Ctrl-C or SIGTERM after steps_run steps (RunOptions::keep_interrupted).
  bool interrupted = false;
  Percentiles step_ms;
  double steps_per_second = 0.0;  ///< timed steps per second of step() time
  Percentiles step_with_collision_ms;
  double steps_per_second_with_collision = 0.0;
};

/// Whether the run stayed within the scene's limits (RunMonitor's rule).
struct StabilityMetrics {
  bool stable = true;
  std::optional<int> diverged_at_step;
  std::string divergence;           ///< why it was stopped ("" when stable)
  double max_speed = 0.0;           ///< m/s, over the free vertices (the judged speed)
  double max_kinetic_energy = 0.0;  ///< J
};

/// What the deformation did to the mesh.
struct ShapeMetrics {
  int max_inverted_tets = 0;
  int final_inverted_tets = 0;        ///< after the last step run (> 0: stuck inverted)
  double volume_change = 0.0;         ///< largest |V(t) - V0| / V0
  double final_elastic_energy = 0.0;  ///< J (NaN for models without one)
};

/// Recovery after the release (RecoveryTracker).
struct RecoveryMetrics {
  bool measured = false;  ///< false when nothing was released or the run diverged
  double residual = 0.0;  ///< RMS distance to the reference shape / bbox diagonal, at the end
  std::optional<double> time_to_one_percent;  ///< s after release; see kRecoveredResidual
};

/// The tool's measures: the instrument's contact, the force of the tool (instrument or grasp).
struct ContactMetrics {
  /// m: deepest tissue vertex inside the instrument (or instrument vertex inside the tissue),
  /// any step
  double max_penetration = 0.0;
  /// m: the same from the instrument's start to its release (pressing and holding; withdrawal
  /// excluded)
  double max_penetration_pressing = 0.0;
  /// Surface vertices that were in contact and lost it while the instrument kept pressing
  /// (the thesis's "floats away" failure); 0 without an instrument.
  int lost_contact_vertices = 0;
  int max_triangle_pairs = 0;    ///< Loading::max_triangle_pairs
  double peak_tool_force = 0.0;  ///< N: largest StepSample::tool_force
  /// m: how far the tool went into the tissue while it loaded it (LoadedTravel): a pressing
  /// instrument, how far it went into the tissue's shape before the load (past first contact); a
  /// grasp, the grasped patch's largest travel while held. 0 without a tool.
  double loaded_travel = 0.0;
  /// Steps that ran out of the instrument's contact_passes with its holds still changing
  /// (SceneStepper::unsettled_contact_steps): each kept a pass the contact would have corrected.
  int unsettled_steps = 0;
};

/// A plausibility warning on a run that may well be stable (plausibility.h judges them): a
/// stable id for scripts and a sentence with the measured value and the threshold it crossed.
struct Warning {
  std::string id;
  std::string message;
};

/// The model's solver and footprint.
struct SolverMetrics {
  double mean_iterations = 0.0;
  int factorizations = 0;
  int linear_solves = 0;
  /// Linear solves that stopped at their iteration cap before their tolerance
  /// (StepStats::truncated_solves): their steps have less than the accuracy asked.
  int truncated_solves = 0;
  double max_constraint_error = 0.0;                             ///< m
  Eigen::Vector3d final_reaction_sum = Eigen::Vector3d::Zero();  ///< N, over all constraints
  std::size_t memory_bytes = 0;
};

/// What one model did on one scene: one entry of metrics.json, a group per struct.
struct ModelRun {
  std::string model;
  nlohmann::json params;  ///< effective parameters, defaults filled in
  int vertices = 0;
  int tets = 0;
  TimingMetrics timing;
  StabilityMetrics stability;
  ShapeMetrics shape;
  RecoveryMetrics recovery;
  ContactMetrics contact;
  SolverMetrics solver;
  /// Against the reference, when the scene asks for an accuracy (filled by the run command).
  std::optional<Accuracy> accuracy;
  /// What is physically implausible in a run that stayed within the scene's limits
  /// (judge_plausibility, filled by run_scene); empty for a plausible or a diverged run.
  std::vector<Warning> warnings;
  /// One per step run, up to kSeriesCapacity steps; of a longer run, one per block of 2, 4, ...
  /// steps (the block's largest tool force), spanning the whole run.
  std::vector<StepSample> samples;
  std::vector<Snapshot> snapshots;  ///< at RunOptions::snapshot_times reached before a blow-up
  std::vector<Snapshot> pictures;   ///< at RunOptions::picture_times reached before a blow-up
};

/// Runs `scene` on `mesh` (read_scene_mesh(scene), or a variant of it) through each requested
/// model in turn, timing every step() with a steady clock and judging each step with
/// RunMonitor. A model that blows up is stopped and reported; the next one runs. Throws
/// InputError for a bad model name or model parameter block.
std::vector<ModelRun> run_scene(const scenes::Scene& scene,
                                const SceneMesh& mesh,
                                const RunOptions& options);
/// The same on the scene's own meshes, read here: for a caller that runs the scene once.
std::vector<ModelRun> run_scene(const scenes::Scene& scene, const RunOptions& options);

}  // namespace softbench::harness
