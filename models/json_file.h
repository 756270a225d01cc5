// SPDX-License-Identifier: MIT
// Reading a JSON file a user hands the CLI (a scene, a sweep run record), bounded so that no
// input can crash the program: nesting is limited, numbers must fit a double, and a folder or a
// missing path is named as such. Every failure is one InputError line naming the file.
#pragma once

#include <nlohmann/json.hpp>

#include <filesystem>
#include <string>
#include <string_view>

namespace softbench {

/// The deepest nesting of arrays and objects accepted. nlohmann::json dumps (and compares)
/// values recursively, so a value nested 100,000 deep overflows the stack; the deepest file we
/// read or write nests about 6 levels, so 64 leaves ample room.
inline constexpr int kMaxJsonDepth = 64;

/// Parses `path` (`//` and `/* */` comments allowed). `what` names the expected kind of file in
/// the message for a folder ("scene file"). Throws InputError:
///   `<path>: no such file`
///   `<path>: is a folder, not a scene file`
///   `<path>: invalid JSON: parse error at line L, column C: ...`
///   `<path>: invalid JSON: number out of range at line L, column C: 1e400 (beyond a double)`
///   `<path>: /description: nested deeper than 64 levels of arrays and objects (the limit)`
nlohmann::json read_json_file(const std::filesystem::path& path,
                              std::string_view what = "JSON file");

/// The same parse of JSON text read elsewhere; `name` stands for the file in the messages.
nlohmann::json parse_json_text(const std::string& text, const std::string& name);

}  // namespace softbench
