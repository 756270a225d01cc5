// SPDX-License-Identifier: MIT
#pragma once

#include <CLI/CLI.hpp>

namespace softbench::harness {

/// `softbench sweep SCENE --param model.key=v1,v2 ... [--model NAME ...] [--out DIR]
/// [--shard i/N] [--reference-model NAME] [--reference-substeps N]`, `softbench merge DIR ...
/// --out DIR` and `softbench recommend SCENE [--sweep DIR]` (harness/sweep.h, recommend.h).
void add_sweep_commands(CLI::App& app);

}  // namespace softbench::harness
