// SPDX-License-Identifier: MIT
// read_json_file: any JSON a user hands the CLI is parsed with bounded nesting, and every
// failure is one line naming the file.
#include "geometry/input_error.h"
#include "models/json_file.h"
#include "tests/test_meshes.h"

#include <gtest/gtest.h>

#include <cstddef>
#include <filesystem>
#include <string>

namespace softbench {
namespace {

std::string error_reading(const std::filesystem::path& file) {
  try {
    read_json_file(file);
  } catch (const InputError& error) {
    return error.what();
  }
  ADD_FAILURE() << "no InputError for " << file;
  return {};
}

std::string nested_arrays(int depth) {
  return std::string(static_cast<std::size_t>(depth), '[')
         + std::string(static_cast<std::size_t>(depth), ']');
}

TEST(ReadJsonFile, ReadsCommentsAndEveryKindOfValue) {
  const test::TempDir dir;
  const auto file = dir.write("a.json", R"({
    // a comment
    "a": [1, -2, 2.5, true, null, "s"], /* another */ "b": {"c": {}}
  })");
  EXPECT_EQ(read_json_file(file),
            nlohmann::json::parse(R"({"a": [1, -2, 2.5, true, null, "s"], "b": {"c": {}}})"));
}

TEST(ReadJsonFile, AcceptsTheDepthLimitAndRejectsOneLevelMore) {
  const test::TempDir dir;
  EXPECT_EQ(read_json_file(dir.write("limit.json", nested_arrays(kMaxJsonDepth))).size(), 1u);
  const auto over = dir.write("over.json", R"({"k/~": )" + nested_arrays(kMaxJsonDepth) + "}");
  EXPECT_EQ(error_reading(over), over.string()
                                     + ": /k~1~0: nested deeper than 64 levels of arrays and "
                                       "objects (the limit)");
}

// Found by fuzz_scene (the same line break in a key): the pointer stays on one line.
TEST(ReadJsonFile, NamesAKeyWithALineBreakOnOneLine) {
  const test::TempDir dir;
  const auto over = dir.write("over.json", R"({"a\nb": )" + nested_arrays(kMaxJsonDepth) + "}");
  EXPECT_EQ(error_reading(over), over.string()
                                     + ": /a\\nb: nested deeper than 64 levels of arrays and "
                                       "objects (the limit)");
}

TEST(ReadJsonFile, NamesTheFileForEveryFailure) {
  const test::TempDir dir;
  const auto broken = dir.write("broken.json", "{\n  \"a\": }\n");
  EXPECT_EQ(error_reading(broken).rfind(broken.string() + ": invalid JSON: parse error at line 2",
                                        0),
            0u)
      << error_reading(broken);
  const auto tiny = dir.write("tiny.json", "[1, -1e400]");
  EXPECT_EQ(error_reading(tiny), tiny.string()
                                     + ": invalid JSON: number out of range at line 1, column 5: "
                                       "-1e400 (beyond a double)");
  EXPECT_EQ(error_reading(dir.path()), dir.path().string() + ": is a folder, not a JSON file");
  EXPECT_EQ(error_reading(dir.path() / "none.json"), (dir.path() / "none.json").string()
                                                         + ": no such file");
}

}  // namespace
}  // namespace softbench
