// SPDX-License-Identifier: MIT
// `softbench compare [SCENE ...]`: the thesis's chapter-3 table, its claims checked, plots.
#include "harness/cli/cli_options.h"
#include "harness/cli/commands.h"
#include "harness/compare/comparison.h"
#include "harness/report/comparison_pictures.h"
#include "harness/report/comparison_plots.h"
#include "harness/report/comparison_report.h"
#include "harness/report/staged_folder.h"
#include "scenes/scene.h"
#include "scenes/shipped_data.h"

#include <chrono>
#include <filesystem>
#include <iomanip>
#include <iostream>
#include <memory>
#include <string>
#include <vector>

namespace softbench::harness {
namespace {

namespace fs = std::filesystem;

struct CompareArguments {
  std::vector<std::string> scenes;
  std::vector<std::string> models;
  std::string out_dir;
  std::string mesh;
  bool no_plots = false;
  bool thesis_only = false;
};

// A shipped scene: scenes/<name> from the working directory (the repository root, as the README
// runs it), else from the source tree this build came from.
fs::path shipped_scene(const std::string& name) {
  const fs::path local = fs::path("scenes") / name;
  std::error_code error;
  if (fs::is_regular_file(local, error)) {
    return local;
  }
  return scenes::shipped_data_dir().parent_path() / name;
}

void compare(const CompareArguments& arguments) {
  const auto start = std::chrono::steady_clock::now();
  std::vector<fs::path> paths;
  if (arguments.scenes.empty()) {
    paths = {shipped_scene("liver_press.json"), shipped_scene("liver_pull.json")};
  } else {
    paths.assign(arguments.scenes.begin(), arguments.scenes.end());
  }
  std::vector<scenes::Scene> scenes;
  for (const fs::path& path : paths) {
    scenes.push_back(load_scene_with_mesh(path.string(), arguments.mesh));
  }
  CompareOptions options;
  options.models = arguments.models;
  options.progress = &std::cerr;
  options.live_progress = live_progress();
  options.matched = !arguments.thesis_only;
  // The folder lands whole (tables and plots) once everything is written, or not at all.
  StagedFolder out(out_dir_or(arguments.out_dir, "out/compare"), "--out");
  Comparison comparison = run_comparison(scenes, options);
  if (!arguments.no_plots) {
    draw_comparison_pictures(out.path(), scenes, comparison, std::cerr);
  }
  write_comparison(out.path(), comparison);
  PlotOutcome plots;
  if (!arguments.no_plots) {
    plots = landed(plot_comparison(out.path()), out);
  }
  out.commit();
  std::cout << comparison_markdown(comparison) << "\nwrote " << (out.path() / "compare.md").string()
            << " and " << (out.path() / "compare.json").string() << "\n";
  if (!arguments.no_plots) {
    print_plot_outcome(plots);
  }
  const double seconds =
      std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  std::cerr << "compare took " << std::fixed << std::setprecision(1) << seconds << " s\n";
}

}  // namespace

void add_compare_command(CLI::App& app) {
  auto arguments = std::make_shared<CompareArguments>();
  CLI::App* command = app.add_subcommand(
      "compare",
      "The thesis's chapter-3 comparison: run scenes through every model; print and write "
      "compare.md, compare.json and PNG plots, with the thesis's claims checked");
  command->add_option("scenes", arguments->scenes,
                      "scene files (default: scenes/liver_press.json scenes/liver_pull.json)");
  add_model_option(*command, arguments->models,
                   "every registered model but the references, plus corotational_fem(linear), "
                   "plain linear FEM");
  add_out_option(*command, arguments->out_dir, "out/compare");
  add_mesh_option(*command, arguments->mesh);
  add_no_plots_flag(*command, arguments->no_plots, "compare.md and compare.json");
  command->add_flag("--thesis-only", arguments->thesis_only,
                    "table A only (the thesis's parameters): no reference, no calibration, no "
                    "table B");
  command->callback([arguments] { compare(*arguments); });
}

}  // namespace softbench::harness
