// SPDX-License-Identifier: MIT
// Calibration of a model whose stiffness is not a material constant (mass_spring's springs,
// shape matching's alpha and beta, Bullet's kLST) to the scene's tissue: its parameters are
// fitted so that it sags and presses as the reference model (which follows the material) does
// on the scene's mesh, material and time step. What is fitted, and how the model takes the
// reference's damping, the model declares itself (ModelInfo::calibration).
#pragma once

#include "harness/calibrate/tissue_response.h"
#include "harness/run/scene_mesh.h"
#include "scenes/scene.h"

#include <nlohmann/json.hpp>

#include <filesystem>
#include <ostream>
#include <string>
#include <vector>

namespace softbench::harness {

struct CalibrationOptions {
  /// The reference whose response is matched: its block from the scene, as run. Any
  /// registered model (the tests fit a model to itself).
  std::string against = "neo_hookean";
  PressSettings press;
  /// Where the reference's response and each calibration are cached (keyed by the scene's
  /// tissue, mesh and tool content, the blocks, the press and the build); empty: no cache.
  std::filesystem::path cache_dir = std::filesystem::path("out") / "calibration";
  std::ostream* progress = nullptr;  ///< a line per run
};

struct Calibration {
  std::string model;
  std::string against;
  TissueResponse reference;  ///< the targets
  TissueResponse fitted;     ///< the model's response with `params`
  /// The effective block (defaults filled in) with the fitted values and the "calibrated"
  /// record: what to paste into the scene's "models".
  nlohmann::json params;
  nlohmann::json values;  ///< the fitted parameters alone, e.g. {"alpha": 0.31, "beta": 0.2}
  std::vector<std::string> targets;  ///< "sag", "force at 0.5 cm", ...
  std::vector<double> errors;        ///< relative error left on each target
  double objective = 0.0;            ///< the fit's cost (see calibration.cpp)
  int evaluations = 0;               ///< model runs the fit took
  double seconds = 0.0;              ///< wall-clock time of the fit (the reference's excluded)
  double reference_seconds = 0.0;    ///< wall-clock time of the reference's runs
  bool cached = false;               ///< read from the cache, nothing run
};

/// Whether `model` has parameters to fit (ModelInfo::calibration); one that follows the
/// material has none.
bool calibratable(const std::string& model);

/// Fits `model`'s declared parameters (a coarse grid over their ranges, then golden-section
/// refinement per parameter) to the reference's static sag and press forces together, from
/// the scene's block for `model` with the declared fixed values and the reference's damping.
/// Deterministic; cached. Throws InputError for a model with nothing to fit, a scene without
/// instrument or fixed region, or a reference that blows up.
Calibration calibrate(const scenes::Scene& scene,
                      const SceneMesh& mesh,
                      const std::string& model,
                      const CalibrationOptions& options = {});

/// The reference's response (cached), as calibrate() matches it.
TissueResponse reference_response(const scenes::Scene& scene,
                                  const SceneMesh& mesh,
                                  const CalibrationOptions& options,
                                  double* seconds = nullptr);

/// `scene_json` (a scene file's JSON) with `model`'s block replaced by `block` and relative
/// mesh paths rewritten for a file in `folder`: the scene `calibrate --write` saves.
nlohmann::json scene_with_block(nlohmann::json scene_json,
                                const std::filesystem::path& scene_file,
                                const std::filesystem::path& folder,
                                const std::string& model,
                                const nlohmann::json& block);

/// "1.234 cm": a length in centimetres with three decimals, for the calibration's messages.
std::string format_cm(double metres);

}  // namespace softbench::harness
