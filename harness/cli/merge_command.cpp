// SPDX-License-Identifier: MIT
// `softbench merge DIR ... --out DIR`: join sweep shards into one table.
#include "harness/cli/cli_options.h"
#include "harness/cli/commands.h"
#include "harness/cli/sweep_output.h"
#include "harness/sweep/sweep.h"

#include <iostream>
#include <memory>
#include <string>
#include <vector>

namespace softbench::harness {
namespace {

void merge(const std::vector<std::string>& dirs, const std::string& out_dir, bool no_plots) {
  std::vector<std::filesystem::path> paths(dirs.begin(), dirs.end());
  const std::vector<SweepRecord> records = read_sweep_runs(paths);
  const std::filesystem::path out(out_dir);
  for (const SweepRecord& record : records) {
    write_sweep_record(out, record);
  }
  const ReferenceConvergence convergence = read_reference_convergence(paths);
  write_reference_convergence(out, convergence);
  write_sweep_table(out, "merged", records, convergence);
  std::cout << records.size() << " runs merged into " << (out / "sweep.csv").string() << "\n";
  print_budgets(records, convergence);
  if (!no_plots) {
    plot_sweep(out);
  }
}

}  // namespace

void add_merge_command(CLI::App& app) {
  auto merge_dirs = std::make_shared<std::vector<std::string>>();
  auto merge_out = std::make_shared<std::string>();
  CLI::App* merge_command =
      app.add_subcommand("merge", "Join sweep folders (shards) into one table");
  merge_command->add_option("dirs", *merge_dirs, "sweep output folders")->required();
  merge_command->add_option("--out", *merge_out, "merged output folder")->required();
  auto no_plots = std::make_shared<bool>(false);
  add_no_plots_flag(*merge_command, *no_plots, "sweep.json and sweep.csv");
  merge_command->callback(
      [merge_dirs, merge_out, no_plots] { merge(*merge_dirs, *merge_out, *no_plots); });
}

}  // namespace softbench::harness
