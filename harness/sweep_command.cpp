// SPDX-License-Identifier: MIT
#include "harness/sweep_command.h"

#include "geometry/input_error.h"
#include "harness/python_plot.h"
#include "harness/recommend.h"
#include "harness/sweep.h"
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

std::filesystem::path default_out(const std::string& scene_name) {
  return std::filesystem::path("out") / "sweep" / scene_name;
}

void plot(const std::filesystem::path& out_dir) {
  print_plot_outcome(
      run_plot_script("plot_sweep.py", "SOFTBENCH_PLOT_SWEEP", out_dir / "sweep.json", out_dir));
}

void print_budgets(const std::vector<SweepRecord>& records) {
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

void sweep(const SweepArguments& arguments) {
  const scenes::Scene scene = scenes::load_scene(arguments.scene);
  SweepOptions options;
  for (const std::string& param : arguments.params) {
    options.axes.push_back(parse_sweep_axis(param));
  }
  options.models = arguments.models;
  std::tie(options.shard, options.shards) = parse_shard(arguments.shard);
  options.out_dir = arguments.out_dir.empty() ? default_out(scene.name)
                                              : std::filesystem::path(arguments.out_dir);
  options.reference.model = arguments.reference_model;
  options.reference.substeps = arguments.reference_substeps;
  options.progress = &std::cerr;
  const std::vector<SweepRecord> records = run_sweep(scene, options);
  write_sweep_table(options.out_dir, scene.name, records);
  std::cout << records.size() << " runs in " << (options.out_dir / "sweep.csv").string() << "\n";
  print_budgets(records);
  plot(options.out_dir);
}

void merge(const std::vector<std::string>& dirs, const std::string& out_dir) {
  std::vector<std::filesystem::path> paths(dirs.begin(), dirs.end());
  const std::vector<SweepRecord> records = read_sweep_runs(paths);
  const std::filesystem::path out(out_dir);
  for (const SweepRecord& record : records) {
    write_sweep_record(out, record);
  }
  write_sweep_table(out, "merged", records);
  std::cout << records.size() << " runs merged into " << (out / "sweep.csv").string() << "\n";
  print_budgets(records);
  plot(out);
}

void recommend_for(const std::string& scene_file, const std::string& sweep_dir) {
  const scenes::Scene scene = scenes::load_scene(scene_file);
  if (!scene.requirements) {
    throw InputError(scene_file + ": /requirements: missing (say what the scene needs: "
                     "steps_per_second, accuracy, outputs)");
  }
  const std::filesystem::path dir =
      sweep_dir.empty() ? default_out(scene.name) : std::filesystem::path(sweep_dir);
  const Recommendation result = recommend(*scene.requirements, read_sweep_runs({dir}));
  std::cout << result.explanation;
}

}  // namespace

void add_sweep_commands(CLI::App& app) {
  auto arguments = std::make_shared<SweepArguments>();
  CLI::App* sweep_command = app.add_subcommand(
      "sweep",
      "Run a grid of model settings on a scene; time each run and measure its error "
      "against the converged reference; write sweep.json, sweep.csv and sweep.png");
  sweep_command->add_option("scene", arguments->scene, "scene file (.json)")->required();
  sweep_command
      ->add_option("--param", arguments->params,
                   "model.key=v1,v2,... (repeatable): a parameter of one model, or model.dt "
                   "for every model's time step (fractions such as 1/60 allowed)")
      ->allow_extra_args(false);
  sweep_command
      ->add_option("--model", arguments->models,
                   "model to sweep (repeatable; default: the "
                   "scene's model blocks)")
      ->allow_extra_args(false);
  sweep_command->add_option("--out", arguments->out_dir,
                            "output folder (default: out/sweep/<scene>)");
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
  sweep_command->callback([arguments] { sweep(*arguments); });

  auto merge_dirs = std::make_shared<std::vector<std::string>>();
  auto merge_out = std::make_shared<std::string>();
  CLI::App* merge_command =
      app.add_subcommand("merge", "Join sweep folders (shards) into one table");
  merge_command->add_option("dirs", *merge_dirs, "sweep output folders")->required();
  merge_command->add_option("--out", *merge_out, "merged output folder")->required();
  merge_command->callback([merge_dirs, merge_out] { merge(*merge_dirs, *merge_out); });

  auto recommend_scene = std::make_shared<std::string>();
  auto recommend_sweep = std::make_shared<std::string>();
  CLI::App* recommend_command = app.add_subcommand(
      "recommend",
      "The cheapest model and settings meeting the scene's requirements, from a sweep");
  recommend_command->add_option("scene", *recommend_scene, "scene file with a requirements block")
      ->required();
  recommend_command->add_option("--sweep", *recommend_sweep,
                                "sweep output folder (default: out/sweep/<scene>)");
  recommend_command->callback(
      [recommend_scene, recommend_sweep] { recommend_for(*recommend_scene, *recommend_sweep); });
}

}  // namespace softbench::harness
