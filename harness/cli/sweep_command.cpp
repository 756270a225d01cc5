// SPDX-License-Identifier: MIT
// `softbench sweep SCENE --param model.key=v1,v2 ...`: speed against error, per setting.
#include "geometry/input_error.h"
#include "harness/cli/cli_options.h"
#include "harness/cli/commands.h"
#include "harness/cli/sweep_output.h"
#include "harness/sweep/sweep.h"
#include "scenes/scene.h"

#include <cstdlib>
#include <iostream>
#include <memory>
#include <string>
#include <vector>

namespace softbench::harness {
namespace {

struct SweepArguments {
  std::string scene;
  std::vector<std::string> params;
  std::vector<std::string> models;
  std::string out_dir;
  std::string shard;
  std::string reference_model = ReferenceSettings{}.model;
  int reference_substeps = ReferenceSettings{}.substeps;
  std::string reference_dir;
  bool trust_reference = false;
  bool reference_only = false;
  bool no_plots = false;
};

// "i/N"; else a Slurm array task (SLURM_ARRAY_TASK_ID of SLURM_ARRAY_TASK_COUNT); else 0/1.
std::pair<int, int> parse_shard(const std::string& text) {
  if (text.empty()) {
    const char* id = std::getenv("SLURM_ARRAY_TASK_ID");
    const char* count = std::getenv("SLURM_ARRAY_TASK_COUNT");
    return id != nullptr && count != nullptr ? std::pair(std::atoi(id), std::atoi(count))
                                             : std::pair(0, 1);
  }
  const std::size_t slash = text.find('/');
  try {
    if (slash != std::string::npos) {
      std::size_t used_i = 0;
      std::size_t used_n = 0;
      const int i = std::stoi(text.substr(0, slash), &used_i);
      const int n = std::stoi(text.substr(slash + 1), &used_n);
      if (used_i == slash && used_n == text.size() - slash - 1 && n >= 1 && i >= 0 && i < n) {
        return {i, n};
      }
    }
  } catch (const std::exception&) {
  }
  throw InputError("--shard " + text + ": expected i/N with 0 <= i < N");
}

void sweep(const SweepArguments& arguments) {
  const scenes::Scene scene = scenes::load_scene(arguments.scene);
  SweepOptions options;
  for (const std::string& param : arguments.params) {
    options.axes.push_back(parse_sweep_axis(param));
  }
  options.models = arguments.models;
  std::tie(options.shard, options.shards) = parse_shard(arguments.shard);
  options.out_dir = out_dir_or(arguments.out_dir, default_sweep_dir(scene.name));
  options.reference.model = arguments.reference_model;
  options.reference.substeps = arguments.reference_substeps;
  options.reference_dir = arguments.reference_dir;
  options.trust_reference = arguments.trust_reference;
  options.reference_only = arguments.reference_only;
  options.progress = &std::cerr;
  const auto [records, convergence] = run_sweep(scene, options);
  if (options.reference_only) {
    const std::string refusal = ranking_refusal(convergence);
    std::cout << "reference ready"
              << (convergence.checked ? "" : " (not checked: --trust-reference)")
              << (refusal.empty() ? "" : "; " + refusal) << "\n";
    return;
  }
  write_sweep_table(options.out_dir, scene.name, records, convergence);
  std::cout << records.size() << " runs in " << (options.out_dir / "sweep.csv").string() << "\n";
  print_budgets(records, convergence);
  if (!arguments.no_plots) {
    plot_sweep(options.out_dir);
  }
}

}  // namespace

void add_sweep_command(CLI::App& app) {
  auto arguments = std::make_shared<SweepArguments>();
  CLI::App* sweep_command = app.add_subcommand(
      "sweep",
      "Run a grid of model settings on a scene; time each run and measure its error "
      "against the converged reference; write sweep.json, sweep.csv and sweep.png");
  add_scene_argument(*sweep_command, arguments->scene);
  sweep_command
      ->add_option("--param", arguments->params,
                   "model.key=v1,v2,... (repeatable): a parameter of one model, or model.dt "
                   "for every model's time step (fractions such as 1/60 allowed)")
      ->allow_extra_args(false);
  add_model_option(*sweep_command, arguments->models,
                   "every model but the reference, with the scene's block or its defaults");
  add_out_option(*sweep_command, arguments->out_dir, "out/sweep/<scene>");
  sweep_command->add_option("--shard", arguments->shard,
                            "i/N: run only every N-th point starting at i (default: a Slurm array "
                            "task's, else all); merge the folders with `softbench merge`");
  sweep_command
      ->add_option("--reference-model", arguments->reference_model, "the converged reference")
      ->capture_default_str();
  sweep_command
      ->add_option("--reference-substeps", arguments->reference_substeps,
                   "the reference's dt is the scene's divided by this")
      ->check(CLI::PositiveNumber)
      ->capture_default_str();
  sweep_command->add_option("--reference-dir", arguments->reference_dir,
                            "where the reference is cached (default: the output folder's "
                            "reference/); shards given one shared folder compute it once");
  sweep_command->add_flag("--trust-reference", arguments->trust_reference,
                          "rank models without checking that the reference converged (the "
                          "check reruns it at twice the substeps)");
  sweep_command->add_flag("--reference-only", arguments->reference_only,
                          "compute the reference and its check into --reference-dir, run no "
                          "model (before a cluster's shards start)");
  add_no_plots_flag(*sweep_command, arguments->no_plots, "sweep.json and sweep.csv");
  sweep_command->callback([arguments] { sweep(*arguments); });
}

}  // namespace softbench::harness
