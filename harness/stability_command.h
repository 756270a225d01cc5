// SPDX-License-Identifier: MIT
#pragma once

#include <CLI/CLI.hpp>

namespace softbench::harness {

/// `softbench stability SCENE [--model NAME ...] [--out DIR] [--quick] [--no-plots]`: the
/// stability map and torture cases of harness/stability.h, written to DIR/stability.json,
/// DIR/stability.md and a heat map per model (DIR/stability_<model>.png, by
/// tools/plot_stability.py). Default out: out/<scene>_stability.
void add_stability_command(CLI::App& app);

}  // namespace softbench::harness
