// SPDX-License-Identifier: MIT
// How every report writes a number: fixed digits in Markdown, null in JSON where it is not finite.
#pragma once

#include <nlohmann/json.hpp>

#include <chrono>
#include <limits>
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

/// `fraction` as a percentage with 3 significant digits ("0.123%", "12.3%", "152%").
std::string percent(double fraction);

/// A measure not taken (written null), and a bound that was never hit.
inline constexpr double kNaN = std::numeric_limits<double>::quiet_NaN();
inline constexpr double kInfinity = std::numeric_limits<double>::infinity();

/// Wall seconds since `start` (a run's time budget, a command's duration).
inline double seconds_since(std::chrono::steady_clock::time_point start) {
  return std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
}

}  // namespace softbench::harness
