// SPDX-License-Identifier: MIT
// How every report writes a number: fixed digits in Markdown, null in JSON where it is not finite.
#pragma once

#include <nlohmann/json.hpp>

#include <string>

namespace softbench::harness {

/// `value` with `digits` digits after the point, for the Markdown tables.
std::string fixed(double value, int digits);
/// A number for JSON, or null where it is NaN or infinite (JSON has neither).
nlohmann::json number_or_null(double value);

}  // namespace softbench::harness
