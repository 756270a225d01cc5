// SPDX-License-Identifier: MIT
#include "harness/report/comparison_plots.h"

namespace softbench::harness {
namespace {

constexpr const char* kScript = "plot_compare.py";
constexpr const char* kScriptVariable = "SOFTBENCH_PLOT_SCRIPT";

}  // namespace

std::optional<std::filesystem::path> plot_script() {
  return find_plot_script(kScript, kScriptVariable);
}

PlotOutcome plot_comparison(const std::filesystem::path& out_dir) {
  return run_plot_script(kScript, kScriptVariable, out_dir / "compare.json", out_dir);
}

}  // namespace softbench::harness
