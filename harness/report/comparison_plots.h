// SPDX-License-Identifier: MIT
#pragma once

#include "harness/report/python_plot.h"

#include <filesystem>
#include <optional>

namespace softbench::harness {

// compare's PNG plots are drawn by matplotlib, driven by tools/plot_compare.py from compare.json
// (the shared plumbing, plotting_python() and PlotOutcome, is harness/report/python_plot.h).

/// tools/plot_compare.py: $SOFTBENCH_PLOT_SCRIPT if set; else the source tree's copy; else
/// beside the running executable (find_plot_script). Empty when none exists.
std::optional<std::filesystem::path> plot_script();

/// Runs the plot script on out_dir/compare.json, writing PNGs into out_dir. A missing Python,
/// matplotlib or script is not an error: the outcome says what is missing and how to get it.
/// A script that fails is reported the same way, with its exit status (its stderr goes to ours).
PlotOutcome plot_comparison(const std::filesystem::path& out_dir);

}  // namespace softbench::harness
