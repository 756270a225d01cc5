// SPDX-License-Identifier: MIT
#pragma once

#include <CLI/CLI.hpp>

namespace softbench::harness {

/// `softbench compare [SCENE ...] [--model NAME ...] [--out DIR] [--mesh PATH] [--no-plots]`:
/// the thesis's chapter-3 comparison (harness/comparison.h). Default scenes: the shipped
/// scenes/liver_press.json and scenes/liver_pull.json; default out: out/compare.
void add_compare_command(CLI::App& app);

}  // namespace softbench::harness
