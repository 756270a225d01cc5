// SPDX-License-Identifier: MIT
// `softbench run SCENE [--model NAME ...] [--out DIR] [--mesh PATH] [--frames-every N]`.
#include "harness/cli/cli_options.h"
#include "harness/cli/commands.h"
#include "harness/report/run_report.h"
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
  const std::filesystem::path out_dir =
      out_dir_or(arguments.out_dir, std::filesystem::path("out") / folder_name(scene.name));
  const SceneMesh mesh = read_scene_mesh(scene);
  RunOptions options;
  options.models = arguments.models;
  options.frames_every = arguments.frames_every;
  options.frames_dir = out_dir / "frames";
  options.progress = &std::cerr;
  options.live_progress = live_progress();
  // Only a scene that asks for an accuracy gets a reference run (cached under out/reference).
  const bool measure_accuracy = scene.requirements && scene.requirements->accuracy;
  const ReferenceSettings reference_settings;
  if (measure_accuracy) {
    options.snapshot_times = comparison_times(scene, reference_settings.times);
  }
  std::vector<ModelRun> runs = run_scene(scene, mesh, options);
  if (measure_accuracy) {
    const ReferenceRun reference =
        reference_run(scene, mesh, reference_settings, std::filesystem::path("out") / "reference");
    for (ModelRun& run : runs) {
      run.accuracy = accuracy_against(run.snapshots, run.contact.peak_tool_force, reference,
                                      mesh.body.rest_positions());
    }
  }
  write_reports(out_dir, scene, runs);
  std::cout << summary_markdown(scene, runs) << "\nwrote " << (out_dir / "metrics.json").string()
            << " and " << (out_dir / "summary.md").string() << "\n";
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
