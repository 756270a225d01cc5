// SPDX-License-Identifier: MIT
// How every report writes a number: fixed digits in Markdown, null in JSON where it is not finite.
#pragma once

#include <nlohmann/json.hpp>

#include <string>

namespace softbench::harness {

/// `value` with `digits` digits after the point, for the Markdown tables.
std::string fixed(double value, int digits);
/// `name` (a scene's, from its file) as one safe file or folder name under out/: every character
/// outside [A-Za-z0-9_.-] becomes '_', as does a leading '.', and it is cut to 100 characters,
/// so a name such as "../../x" cannot place the output outside out/ (scenes/README.md).
std::string folder_name(const std::string& name);

/// A number for JSON, or null where it is NaN or infinite (JSON has neither).
nlohmann::json number_or_null(double value);

}  // namespace softbench::harness
