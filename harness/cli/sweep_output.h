// SPDX-License-Identifier: MIT
// What the sweep, merge and recommend commands share: where a sweep lands by default, and how
// its table is summarised and drawn.
#pragma once

#include "harness/sweep/sweep.h"

#include <filesystem>
#include <string>
#include <vector>

namespace softbench::harness {

/// out/sweep/<scene> (the name made safe by folder_name()).
std::filesystem::path default_sweep_dir(const std::string& scene_name);
/// Draws out_dir/sweep.png from out_dir/sweep.json (tools/plot_sweep.py).
void plot_sweep(const std::filesystem::path& out_dir);
/// The fastest run within 1%, 5% and 20% error, one line each, on stdout; against a reference
/// that did not converge, why nothing is ranked.
void print_budgets(const std::vector<SweepRecord>& records,
                   const ReferenceConvergence& convergence);

}  // namespace softbench::harness
