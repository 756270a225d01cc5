// SPDX-License-Identifier: MIT
// `softbench stability SCENE`: the stability map and the torture cases.
#include "harness/cli/cli_options.h"
#include "harness/cli/commands.h"
#include "harness/report/python_plot.h"
#include "harness/report/stability_report.h"
#include "harness/report/staged_folder.h"
#include "harness/stability/stability.h"
#include "scenes/scene.h"

#include <filesystem>
#include <iomanip>
#include <iostream>
#include <memory>
#include <string>
#include <vector>

namespace softbench::harness {
namespace {

struct StabilityArguments {
  std::string scene;
  std::vector<std::string> models;
  std::string out_dir;
  bool quick = false;
  double recovery_window = 0.0;
  double max_wall = 0.0;
  bool no_plots = false;
};

void stability(const StabilityArguments& arguments) {
  const scenes::Scene scene = scenes::load_scene(arguments.scene);
  StagedFolder out(out_dir_or(arguments.out_dir, std::filesystem::path("out")
                                                     / folder_name(scene.name + "_stability")),
                   "--out");
  StabilityOptions options;
  options.models = arguments.models;
  options.settings = arguments.quick ? quick_stability_settings() : default_stability_settings();
  if (arguments.recovery_window > 0.0) {
    options.settings.recovery_window = arguments.recovery_window;
  }
  if (arguments.max_wall > 0.0) {
    options.settings.max_wall_seconds_per_run = arguments.max_wall;
  }
  options.progress = &std::cerr;
  const StabilityReport report = run_stability(scene, options);
  write_stability(out.path(), report);
  PlotOutcome plots;
  if (!arguments.no_plots) {
    plots = landed(run_plot_script("plot_stability.py", "SOFTBENCH_STABILITY_SCRIPT",
                                   out.path() / "stability.json", out.path()),
                   out);
  }
  out.commit();
  std::cout << stability_markdown(report) << "\nwrote " << (out.path() / "stability.md").string()
            << " and " << (out.path() / "stability.json").string() << "\n";
  if (!arguments.no_plots) {
    print_plot_outcome(plots);
  }
  std::cerr << "stability took " << std::fixed << std::setprecision(1) << report.wall_seconds
            << " s\n";
}

}  // namespace

void add_stability_command(CLI::App& app) {
  auto arguments = std::make_shared<StabilityArguments>();
  CLI::App* command = app.add_subcommand(
      "stability",
      "Map each model's largest stable time step against stiffness and run the torture cases "
      "(squash, collapse, scramble, stretch 3x, nu = 0.49, sliver tet); write stability.md, "
      "stability.json and a PNG heat map per model, with the thesis's claims checked");
  add_scene_argument(*command, arguments->scene);
  add_model_option(*command, arguments->models, "every registered model but the references");
  add_out_option(*command, arguments->out_dir, "out/<scene>_stability");
  command->add_flag("--quick", arguments->quick,
                    "a small grid (2 stiffnesses, dt 1/30..1/120 s, short runs) for tests and CI");
  command
      ->add_option("--recovery-window", arguments->recovery_window,
                   "s of recovery after each torture (default: 10, with --quick 2)")
      ->check(CLI::PositiveNumber);
  command
      ->add_option("--max-wall", arguments->max_wall,
                   "s of wall time per run before it is reported as timed out (default: 30, "
                   "with --quick 10)")
      ->check(CLI::PositiveNumber);
  add_no_plots_flag(*command, arguments->no_plots, "stability.md and stability.json");
  command->callback([arguments] { stability(*arguments); });
}

}  // namespace softbench::harness
