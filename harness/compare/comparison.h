// SPDX-License-Identifier: MIT
#pragma once

#include "harness/claim.h"
#include "harness/compare/equal_accuracy.h"
#include "harness/run/runner.h"
#include "scenes/scene.h"

#include <nlohmann/json.hpp>

#include <filesystem>
#include <map>
#include <optional>
#include <ostream>
#include <string>
#include <string_view>
#include <vector>

namespace softbench::harness {

// The thesis's chapter-3 comparison (section 3.5): the same scenes through every model, with the
// thesis's figures beside ours and its claims turned into checks with measured evidence.

/// A row of the comparison: a registered model, or a variant of one with some parameters
/// overridden and its own label.
struct ModelVariant {
  std::string label;         ///< as reported, e.g. "corotational_fem(linear)"
  std::string model;         ///< the registered model that runs
  nlohmann::json overrides;  ///< merged over the scene's parameter block for `model`
};

/// The variants compare knows: "corotational_fem(linear)", plain linear FEM (formulation
/// "linear"), which the thesis's claim about FEM and large deformation needs beside the
/// corotational FEM.
const std::vector<ModelVariant>& known_variants();

/// The rows to run for `names` (registered model names or variant labels, in that order).
/// Empty: every registered model, each known variant right after its base model. Throws
/// InputError for a name that is neither (listing both kinds).
std::vector<ModelVariant> resolve_models(const std::vector<std::string>& names);

/// The thesis's speed for a row (FPS on an Intel Core i3-2100 with rendering, section 3.5.1):
/// mass-spring 335.7, FEM 36.5 (beside both FEM rows: the thesis says only "FEM"), shape
/// matching 787. Empty for the rows it has no figure for.
std::optional<double> thesis_steps_per_second(std::string_view label);

/// One scene's runs. ModelRun::model holds the row label (a variant's label, not its model).
struct SceneComparison {
  std::string name;
  nlohmann::json scene;  ///< the effective scene as run (scenes::to_json), mesh override included
  std::vector<ModelRun> runs;
};

/// The thresholds that turn the thesis's words into measurements (recovered: below
/// kRecoveredResidual, as everywhere).
struct ClaimCriteria {
  /// Distorted: an inverted (folded) tet at any step, which a viewer sees as a crease or a
  /// surface turned inside out.
  int max_inverted_tets = 0;
  /// Linear FEM's spurious volume growth under rotation: unfit when its largest volume change
  /// exceeds the corotational FEM's by this factor and by at least `volume_margin`.
  double volume_ratio = 2.0;
  double volume_margin = 0.01;  ///< absolute, as a fraction of the rest volume
};

/// The three chapter-3 claims, checked on every scene: (1) shape matching recovers from every
/// deformation without distortion; (2) mass-spring may fail to recover from a large deformation;
/// (3) linear FEM is unfit for large deformation while corotational FEM is fit.
std::vector<Claim> check_claims(const std::vector<SceneComparison>& scenes,
                                const ClaimCriteria& criteria = {});

/// One scene's runs matched to the tissue (table B): each row's model calibrated to the reference
/// where its stiffness is not a material constant (harness/calibrate/calibration.h), the same
/// block as table A's where it follows the material, and every run measured against the
/// converged reference (ModelRun::accuracy).
struct MatchedScene {
  std::string name;
  std::string reference;       ///< the reference model
  std::vector<ModelRun> runs;  ///< labelled as in table A, each with its accuracy
  /// Per row label, for a calibrated row: {"values", "targets", "errors", "evaluations",
  /// "seconds", "cached"}.
  std::map<std::string, nlohmann::json> calibrations;
  std::vector<std::string> notes;  ///< what could not be matched, and why
};

/// A picture file beside compare.md (harness/report/pictures.h): one table's runs of one scene,
/// a row per run (the table's order), a column per time.
struct ComparisonPicture {
  std::string scene;
  std::string table;             ///< "A" or "B"
  std::string file;              ///< relative to compare.md
  std::vector<double> times;     ///< s, the columns
  std::vector<std::string> rows;  ///< run labels
};

struct Comparison {
  std::vector<SceneComparison> scenes;
  /// Table B, one per scene (empty when not asked for). The claims are judged on it when
  /// present, on table A otherwise.
  std::vector<MatchedScene> matched;
  /// The speed-accuracy trade on the first scene that presses (empty if none, or not asked).
  std::optional<EqualAccuracy> equal_accuracy;
  std::vector<Claim> claims;
  ClaimCriteria criteria;
  std::string machine;  ///< where ours were measured (CPU model), for the reader
  /// The pictures written beside the report (the command draws them; not in compare.json).
  std::vector<ComparisonPicture> pictures;
};

struct CompareOptions {
  std::vector<std::string> models;  ///< see resolve_models()
  int warmup_steps = 10;            ///< RunOptions::warmup_steps
  std::ostream* progress = nullptr;
  bool live_progress = false;
  /// Table B too: calibrate, run again, measure against the reference (cached under these).
  bool matched = true;
  /// With table B: the equal-accuracy table on the first scene whose instrument presses.
  bool equal_accuracy = true;
  std::filesystem::path reference_dir = std::filesystem::path("out") / "reference";
  std::filesystem::path calibration_dir = std::filesystem::path("out") / "calibration";
};

/// The thesis's speed ratios against its FEM (section 3.5.1: shape matching 787 / 36.5 = 21.6,
/// mass-spring 335.7 / 36.5 = 9.2) and ours from `runs` (steps/s with collision against
/// corotational_fem's): {label, thesis ratio, our ratio or nullopt when a row is missing}.
struct SpeedRatio {
  std::string label;
  double thesis = 0.0;
  std::optional<double> ours;
};
std::vector<SpeedRatio> speed_ratios(const std::vector<ModelRun>& runs);

/// Runs every scene through every row (run_scene, one row at a time), then, when
/// options.matched, table B (the reference, the calibrations, the rows again), and checks the
/// claims.
/// Throws InputError for an unknown model name before any model runs, and for a bad parameter
/// block or mesh when its scene's turn comes.
Comparison run_comparison(const std::vector<scenes::Scene>& scenes, const CompareOptions& options);

}  // namespace softbench::harness
