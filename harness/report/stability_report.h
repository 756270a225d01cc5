// SPDX-License-Identifier: MIT
#pragma once

#include "harness/stability/stability.h"

#include <nlohmann/json.hpp>

#include <filesystem>
#include <string>

namespace softbench::harness {

/// stability.json: the settings, per model its axis, map (every cell with its verdict) and
/// torture cases, and the claims. tools/plot_stability.py draws the heat maps from it.
nlohmann::json stability_json(const StabilityReport& report);

/// stability.md: the claims, the largest stable time step per model and stiffness, and per model
/// per torture case stable / recovered / NaN / inverted tets.
std::string stability_markdown(const StabilityReport& report);

/// Writes out_dir/stability.json and out_dir/stability.md, each atomically.
void write_stability(const std::filesystem::path& out_dir, const StabilityReport& report);

}  // namespace softbench::harness
