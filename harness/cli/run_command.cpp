// SPDX-License-Identifier: MIT
// `softbench run SCENE [--model NAME ...] [--out DIR] [--mesh PATH] [--frames-every N]`.
#include "harness/cli/cli_options.h"
#include "harness/cli/commands.h"
#include "harness/interrupt.h"
#include "harness/report/run_report.h"
#include "harness/report/staged_folder.h"
#include "harness/run/reference.h"
#include "harness/run/runner.h"

#include <iostream>
#include <memory>
#include <string>
#include <vector>

namespace softbench::harness {
namespace {

struct RunArguments {
  std::string scene;
  std::vector<std::string> models;
  std::string out_dir;
  std::string mesh;
  int frames_every = 0;
};

void run(const RunArguments& arguments) {
  const scenes::Scene scene = load_scene_with_mesh(arguments.scene, arguments.mesh);
  // The folder lands whole once every file is written, or not at all.
  StagedFolder out(
      out_dir_or(arguments.out_dir, std::filesystem::path("out") / folder_name(scene.name)),
      "--out");
  const SceneMesh mesh = read_scene_mesh(scene);
  RunOptions options;
  options.models = arguments.models;
  options.frames_every = arguments.frames_every;
  options.frames_dir = out.path() / "frames";
  options.progress = &std::cerr;
  options.live_progress = live_progress();
  // Only a scene that asks for an accuracy gets a reference run (cached under out/reference).
  const bool measure_accuracy = scene.requirements && scene.requirements->accuracy;
  const ReferenceSettings reference_settings;
  if (measure_accuracy) {
    options.snapshot_times = comparison_times(scene, reference_settings.times);
  }
  // Ctrl-C or SIGTERM ends the run after the current step; what was measured is written,
  // marked interrupted, and the command still ends with status 130.
  options.keep_interrupted = true;
  std::vector<ModelRun> runs = run_scene(scene, mesh, options);
  const bool interrupted = !runs.empty() && runs.back().timing.interrupted;
  if (measure_accuracy && !interrupted) {
    const ReferenceRun reference =
        reference_run(scene, mesh, reference_settings, std::filesystem::path("out") / "reference");
    for (ModelRun& run : runs) {
      run.accuracy = accuracy_against(run.snapshots, run.contact.peak_tool_force, reference,
                                      mesh.body.rest_positions());
    }
  }
  write_reports(out.path(), scene, runs);
  out.commit();
  std::cout << summary_markdown(scene, runs) << "\nwrote " << (out.path() / "metrics.json").string()
            << " and " << (out.path() / "summary.md").string() << "\n";
  if (interrupted) {
    throw Interrupted("stopped after step " + std::to_string(runs.back().timing.steps_run)
                      + " of " + runs.back().model + "; what was measured is in "
                      + (out.path() / "metrics.json").string() + ", marked interrupted");
  }
}

}  // namespace

void add_run_command(CLI::App& app) {
  auto arguments = std::make_shared<RunArguments>();
  CLI::App* command = app.add_subcommand(
      "run", "Run a scene through models; write metrics.json, summary.md and optional frames");
  add_scene_argument(*command, arguments->scene);
  add_model_option(*command, arguments->models, "every registered model but the references");
  add_out_option(*command, arguments->out_dir, "out/<scene>");
  add_mesh_option(*command, arguments->mesh);
  command
      ->add_option("--frames-every", arguments->frames_every,
                   "write a ParaView .vtu frame every N steps (0: none)")
      ->check(CLI::NonNegativeNumber);
  command->callback([arguments] { run(*arguments); });
}

}  // namespace softbench::harness
