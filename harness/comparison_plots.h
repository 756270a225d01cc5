// SPDX-License-Identifier: MIT
#pragma once

#include <filesystem>
#include <optional>
#include <string>
#include <vector>

namespace softbench::harness {

// compare's PNG plots are drawn by matplotlib, driven by tools/plot_compare.py from compare.json:
// softbench draws no pixels itself.

/// tools/plot_compare.py: $SOFTBENCH_PLOT_SCRIPT if set; else the source tree's copy (the
/// SOFTBENCH_TOOLS_DIR compile definition: a build runs from its source tree); else
/// plot_compare.py or ../tools/plot_compare.py beside the running executable (an installed or
/// copied layout). Empty when none exists.
std::optional<std::filesystem::path> plot_script();

/// The first Python that can import matplotlib: $SOFTBENCH_PYTHON if set, else `python3` on the
/// PATH, else /usr/bin/python3 (Debian's python3-matplotlib lives there, and a pyenv or venv
/// python3 on the PATH may lack it). Empty when none can.
std::optional<std::string> plotting_python();

struct PlotOutcome {
  bool plotted = false;
  std::string message;  ///< why nothing was plotted (a warning for the user), else ""
  std::vector<std::filesystem::path> files;  ///< the PNGs written, sorted
};

/// Runs the plot script on out_dir/compare.json, writing PNGs into out_dir. A missing Python,
/// matplotlib or script is not an error: the outcome says what is missing and how to get it.
/// A script that fails is reported the same way, with its exit status (its stderr goes to ours).
PlotOutcome plot_comparison(const std::filesystem::path& out_dir);

}  // namespace softbench::harness
