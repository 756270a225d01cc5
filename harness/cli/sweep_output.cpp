// SPDX-License-Identifier: MIT
#include "harness/cli/sweep_output.h"

#include "harness/cli/cli_options.h"
#include "harness/report/python_plot.h"

#include <iostream>
#include <optional>

namespace softbench::harness {

std::filesystem::path default_sweep_dir(const std::string& scene_name) {
  return std::filesystem::path("out") / "sweep" / folder_name(scene_name);
}

void plot_sweep(const std::filesystem::path& out_dir) {
  print_plot_outcome(
      run_plot_script("plot_sweep.py", "SOFTBENCH_PLOT_SWEEP", out_dir / "sweep.json", out_dir));
}

void print_budgets(const std::vector<SweepRecord>& records,
                   const ReferenceConvergence& convergence) {
  if (const std::string refusal = ranking_refusal(convergence); !refusal.empty()) {
    std::cout << "not ranked: " << refusal << "\n";
    return;
  }
  for (const double budget : {0.01, 0.05, 0.2}) {
    const std::optional<SweepRecord> best = fastest_within(records, budget);
    std::cout << "error <= " << 100 * budget << "%: ";
    if (best) {
      std::cout << best->point.model << " " << best->point.settings.dump() << " at "
                << best->steps_per_second << " steps/s (error " << 100 * best->accuracy.rms_error
                << "%)\n";
    } else {
      std::cout << "no run\n";
    }
  }
}

}  // namespace softbench::harness
