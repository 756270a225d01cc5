// SPDX-License-Identifier: MIT
#pragma once

#include "harness/soak/soak.h"

#include <nlohmann/json.hpp>

#include <filesystem>
#include <string>

namespace softbench::harness {

/// soak.json: provenance, the soak's settings, its verdict and summary, and every kept cycle.
nlohmann::json soak_json(const SoakReport& report);

/// soak.md: the verdict, memory after warm-up and at the end, energy and shape drift, speed
/// drift, then the cycles at ten points over the soak.
std::string soak_markdown(const SoakReport& report);

/// Writes out_dir/soak.json and out_dir/soak.md, each atomically.
void write_soak(const std::filesystem::path& out_dir, const SoakReport& report);

}  // namespace softbench::harness
