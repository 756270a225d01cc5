// SPDX-License-Identifier: MIT
#pragma once

#include "harness/compare/comparison.h"

#include <nlohmann/json.hpp>

#include <filesystem>
#include <string>

namespace softbench::harness {

/// compare.json's schema version ("softbench_compare"); bump it when a key changes meaning.
inline constexpr int kCompareSchemaVersion = 4;

/// compare.json: provenance, the thesis's figures, the criteria, per scene each run as
/// metrics.json writes it (model_run_json.h) with the thesis's figure beside it
/// ("thesis_steps_per_second"), and the claims with their evidence. tools/plot_compare.py
/// reads it.
nlohmann::json comparison_json(const Comparison& comparison);

/// The inverse of comparison_json() for the fields it writes. Throws InputError naming the JSON
/// pointer when a key is missing or has the wrong type, or the schema version differs.
Comparison comparison_from_json(const nlohmann::json& json);

/// compare.md: per scene the chapter-3 table (thesis FPS beside our steps/s, simulation only and
/// with collision; stability; recovery; penetration; instrument force; volume change; the
/// plausibility warnings, listed under the table), then the claims with pass/fail and their
/// evidence.
std::string comparison_markdown(const Comparison& comparison);

/// Writes out_dir/compare.json and out_dir/compare.md, each atomically.
void write_comparison(const std::filesystem::path& out_dir, const Comparison& comparison);

}  // namespace softbench::harness
