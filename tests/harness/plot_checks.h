// SPDX-License-Identifier: MIT
#pragma once

#include "harness/report/python_plot.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <filesystem>
#include <fstream>
#include <initializer_list>
#include <string>

namespace softbench::test {

/// Each of `names` is among the outcome's files in `dir` and starts with the PNG signature.
inline void expect_png_files(const harness::PlotOutcome& plots,
                             const std::filesystem::path& dir,
                             std::initializer_list<const char*> names) {
  for (const char* name : names) {
    const std::filesystem::path png = dir / name;
    ASSERT_NE(std::find(plots.files.begin(), plots.files.end(), png), plots.files.end()) << name;
    std::ifstream file(png, std::ios::binary);
    std::string magic(8, '\0');
    file.read(magic.data(), 8);
    EXPECT_EQ(magic, std::string("\x89PNG\r\n\x1a\n", 8)) << name;
  }
}

}  // namespace softbench::test
