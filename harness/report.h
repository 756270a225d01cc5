// SPDX-License-Identifier: MIT
#pragma once

#include "harness/runner.h"
#include "scenes/scene.h"

#include <nlohmann/json.hpp>

#include <filesystem>
#include <string>
#include <vector>

namespace softbench::harness {

/// `value` with `digits` digits after the point, for the Markdown tables.
std::string fixed(double value, int digits);

/// A number for JSON, or null where it is NaN or infinite (JSON has neither).
nlohmann::json number_or_null(double value);

/// One metrics.json entry (DESIGN.md's schema plus solver, energy and memory figures).
nlohmann::json to_json(const ModelRun& run);

/// The whole metrics.json: the effective scene, then one entry per model run.
nlohmann::json metrics_json(const scenes::Scene& scene, const std::vector<ModelRun>& runs);

/// A Markdown table a person reads: one row per model.
std::string summary_markdown(const scenes::Scene& scene, const std::vector<ModelRun>& runs);

/// Writes out_dir/metrics.json and out_dir/summary.md, each atomically (temporary + rename), so
/// an interrupted run never leaves a half-written file.
void write_reports(const std::filesystem::path& out_dir,
                   const scenes::Scene& scene,
                   const std::vector<ModelRun>& runs);

}  // namespace softbench::harness
