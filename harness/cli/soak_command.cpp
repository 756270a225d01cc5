// SPDX-License-Identifier: MIT
// `softbench soak SCENE --model NAME [--steps N] [--out DIR] [--mesh PATH]`.
#include "harness/cli/cli_options.h"
#include "harness/cli/commands.h"
#include "harness/interrupt.h"
#include "harness/report/soak_report.h"
#include "harness/report/staged_folder.h"
#include "harness/soak/soak.h"

#include <iostream>
#include <memory>
#include <string>

namespace softbench::harness {
namespace {

struct SoakArguments {
  std::string scene;
  std::string model;
  long long steps = 1000000;
  std::string out_dir;
  std::string mesh;
};

void soak(const SoakArguments& arguments) {
  const scenes::Scene scene = load_scene_with_mesh(arguments.scene, arguments.mesh);
  // The folder lands whole once both files are written, or not at all.
  StagedFolder out(out_dir_or(arguments.out_dir,
                              std::filesystem::path("out")
                                  / folder_name(scene.name + "_soak_" + arguments.model)),
                   "--out");
  const SceneMesh mesh = read_scene_mesh(scene);
  SoakOptions options;
  options.model = arguments.model;
  options.steps = arguments.steps;
  options.progress = &std::cerr;
  options.live_progress = live_progress();
  // Ctrl-C or SIGTERM (a batch system's time limit) ends the soak after the current step; what
  // the whole cycles measured is written, marked interrupted, and the command ends with 130.
  options.keep_interrupted = true;
  const SoakReport report = run_soak(scene, mesh, options);
  write_soak(out.path(), report);
  out.commit();
  std::cout << soak_markdown(report) << "\nwrote " << (out.path() / "soak.md").string() << " and "
            << (out.path() / "soak.json").string() << "\n";
  if (report.interrupted) {
    throw Interrupted("stopped after step " + std::to_string(report.steps_run) + " of "
                      + std::to_string(report.steps_planned) + "; what the whole cycles measured "
                      "is in " + (out.path() / "soak.json").string() + ", marked interrupted");
  }
}

}  // namespace

void add_soak_command(CLI::App& app) {
  auto arguments = std::make_shared<SoakArguments>();
  CLI::App* command = app.add_subcommand(
      "soak",
      "Drive one model through the scene's loading cycle after cycle (the instrument presses "
      "and withdraws, the grasp pulls and lets go) for N steps; report resident memory, heap in "
      "use, energy and shape drift, and speed per cycle in soak.md and soak.json. A blow-up ends the soak "
      "and is reported (exit 0)");
  add_scene_argument(*command, arguments->scene);
  command->add_option("--model", arguments->model, "the model to soak")->required();
  command->add_option("--steps", arguments->steps, "steps in all (default 1,000,000)")
      ->check(CLI::Range(1LL, kMaxSoakSteps));
  add_out_option(*command, arguments->out_dir, "out/<scene>_soak_<model>");
  add_mesh_option(*command, arguments->mesh);
  command->callback([arguments] { soak(*arguments); });
}

}  // namespace softbench::harness
