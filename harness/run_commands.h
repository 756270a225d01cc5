// SPDX-License-Identifier: MIT
#pragma once

#include <CLI/CLI.hpp>

namespace softbench::harness {

/// `softbench run SCENE [--model NAME ...] [--out DIR] [--frames-every N]` and
/// `softbench models [--json]`.
void add_run_commands(CLI::App& app);

}  // namespace softbench::harness
