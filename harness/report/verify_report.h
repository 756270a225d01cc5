// SPDX-License-Identifier: MIT
#pragma once

#include "harness/verify/verify.h"

#include <nlohmann/json.hpp>

#include <filesystem>
#include <string>

namespace softbench::harness {

/// verify.json's schema: raised when a key changes meaning or goes away.
inline constexpr int kVerifySchemaVersion = 1;

/// verify.json: schema_version, provenance, the settings, and per model per case its status,
/// note, measures (value, target, tolerance, what it is), wall time and details.
nlohmann::json verify_json(const VerifyReport& report);

/// verify.md: a table with a row per model and a column per case, each cell the case's headline
/// value and PASS / FAIL / n/a, the tolerances, and the notes under it.
std::string verify_markdown(const VerifyReport& report);

/// Writes out_dir/verify.json and out_dir/verify.md, each atomically, both made before either is
/// written.
void write_verify(const std::filesystem::path& out_dir, const VerifyReport& report);

}  // namespace softbench::harness
