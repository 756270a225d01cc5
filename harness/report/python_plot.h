// SPDX-License-Identifier: MIT
#pragma once

#include "harness/report/staged_folder.h"

#include <filesystem>
#include <optional>
#include <string>
#include <vector>

namespace softbench::harness {

// The harness's PNG plots are drawn by matplotlib, driven by a script in tools/ that reads the
// JSON a command wrote: softbench draws no pixels itself. This is the plumbing every such command
// shares (compare: comparison_plots.h; stability: stability_command.cpp).

/// tools/<name>: $<env_var> if set (and a file); else the source tree's copy (the
/// SOFTBENCH_TOOLS_DIR compile definition: a build runs from its source tree); else <name> or
/// ../tools/<name> beside the running executable (an installed or copied layout). Empty when
/// none exists.
std::optional<std::filesystem::path> find_plot_script(const std::string& name, const char* env_var);

/// The first Python that can import matplotlib: $SOFTBENCH_PYTHON if set, else `python3` on the
/// PATH, else /usr/bin/python3 (Debian's python3-matplotlib lives there, and a pyenv or venv
/// python3 on the PATH may lack it). Empty when none can.
std::optional<std::string> plotting_python();

struct PlotOutcome {
  bool plotted = false;
  std::string message;  ///< why nothing was plotted (a warning for the user), else ""
  std::vector<std::filesystem::path> files;  ///< the PNGs written, sorted
};

/// Runs `python tools/<script_name> <json_file> --out <out_dir>`; the script prints each file it
/// wrote, one per line. A missing Python, matplotlib or script is not an error: the outcome says
/// what is missing and how to get it (`env_var` names the override for the script's path). A
/// script that fails is reported the same way, with its exit status (its stderr goes to ours).
PlotOutcome run_plot_script(const std::string& script_name,
                            const char* env_var,
                            const std::filesystem::path& json_file,
                            const std::filesystem::path& out_dir);

/// What the commands print of an outcome: "wrote FILE" per plot on stdout, or the reason for no
/// plots as a warning on stderr.
void print_plot_outcome(const PlotOutcome& outcome);

/// The outcome of plots written into `folder` before it was committed, with the files where
/// they land.
PlotOutcome landed(PlotOutcome outcome, const StagedFolder& folder);

}  // namespace softbench::harness
