// SPDX-License-Identifier: MIT
#pragma once

#include "harness/format.h"
#include "harness/run/runner.h"
#include "scenes/scene.h"

#include <nlohmann/json.hpp>

#include <filesystem>
#include <string>
#include <vector>

namespace softbench::harness {

/// The whole metrics.json: provenance, the effective scene, then one entry per model run
/// (model_run_json.h).
nlohmann::json metrics_json(const scenes::Scene& scene, const std::vector<ModelRun>& runs);

/// A run's plausibility warnings for a table cell: their ids, comma-separated, or "none".
std::string warnings_cell(const ModelRun& run);
/// The warnings of `runs` as a Markdown list under their table ("" when there are none): one
/// item per warning, "- **model**: id: message".
std::string warnings_markdown(const std::vector<ModelRun>& runs);

/// A Markdown table a person reads: one row per model, its plausibility warnings after it.
std::string summary_markdown(const scenes::Scene& scene, const std::vector<ModelRun>& runs);

/// Writes out_dir/metrics.json and out_dir/summary.md, each atomically (temporary + rename), so
/// an interrupted run never leaves a half-written file.
void write_reports(const std::filesystem::path& out_dir,
                   const scenes::Scene& scene,
                   const std::vector<ModelRun>& runs);

}  // namespace softbench::harness
