// SPDX-License-Identifier: MIT
#include "harness/run_commands.h"

#include "geometry/mesh_io.h"
#include "geometry/mesh_validation.h"
#include "harness/mesh_override.h"
#include "harness/reference.h"
#include "harness/report.h"
#include "harness/runner.h"
#include "harness/sweep.h"
#include "models/model_registry.h"
#include "scenes/scene.h"

#include <unistd.h>

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
  scenes::Scene scene = scenes::load_scene(arguments.scene);
  if (!arguments.mesh.empty()) {
    override_mesh(scene, arguments.mesh);
  }
  const std::filesystem::path out_dir = arguments.out_dir.empty()
                                            ? std::filesystem::path("out") / scene.name
                                            : std::filesystem::path(arguments.out_dir);
  RunOptions options;
  options.models = arguments.models;
  options.frames_every = arguments.frames_every;
  options.frames_dir = out_dir / "frames";
  options.progress = &std::cerr;
  options.live_progress = ::isatty(STDERR_FILENO) != 0;
  // Only a scene that asks for an accuracy gets a reference run (cached under out/reference).
  const bool measure_accuracy = scene.requirements && scene.requirements->accuracy;
  const ReferenceSettings reference_settings;
  if (measure_accuracy) {
    options.snapshot_times = comparison_times(scene, reference_settings.times);
  }
  std::vector<ModelRun> runs = run_scene(scene, options);
  if (measure_accuracy) {
    const ReferenceRun reference =
        reference_run(scene, reference_settings, std::filesystem::path("out") / "reference");
    const Eigen::Matrix3Xd rest = make_tet_mesh(read_mesh(scene.mesh)).rest_positions();
    for (ModelRun& run : runs) {
      run.accuracy = accuracy_against(run, reference, rest);
    }
  }
  write_reports(out_dir, scene, runs);
  std::cout << summary_markdown(scene, runs) << "\nwrote " << (out_dir / "metrics.json").string()
            << " and " << (out_dir / "summary.md").string() << "\n";
}

void list_models(bool json) {
  const ModelRegistry& registry = builtin_models();
  if (json) {
    nlohmann::json list = nlohmann::json::array();
    for (const std::string& name : registry.names()) {
      const ModelInfo& info = registry.at(name);
      nlohmann::json parameters = nlohmann::json::array();
      for (const ParameterDoc& doc : info.parameters) {
        parameters.push_back(
            {{"name", doc.name}, {"default", doc.default_value}, {"description", doc.description}});
      }
      list.push_back({{"name", name}, {"summary", info.summary}, {"parameters", parameters}});
    }
    std::cout << list.dump(2) << "\n";
    return;
  }
  for (const std::string& name : registry.names()) {
    const ModelInfo& info = registry.at(name);
    std::cout << name << ": " << info.summary << "\n";
    for (const ParameterDoc& doc : info.parameters) {
      std::cout << "  " << doc.name << " = " << doc.default_value.dump() << "  (" << doc.description
                << ")\n";
    }
  }
}

}  // namespace

void add_run_commands(CLI::App& app) {
  auto run_arguments = std::make_shared<RunArguments>();
  CLI::App* run_command = app.add_subcommand(
      "run", "Run a scene through models; write metrics.json, summary.md and optional frames");
  run_command->add_option("scene", run_arguments->scene, "scene file (.json)")->required();
  run_command
      ->add_option("--model", run_arguments->models,
                   "model to run (repeatable; default: every registered model)")
      ->allow_extra_args(false);  // one name per --model: a scene after it stays a scene
  run_command->add_option("--out", run_arguments->out_dir, "output folder (default: out/<scene>)");
  run_command->add_option("--mesh", run_arguments->mesh,
                          "replace the scene's mesh (e.g. SOFA's liver.msh for sofa_liver.json)");
  run_command
      ->add_option("--frames-every", run_arguments->frames_every,
                   "write a ParaView .vtu frame every N steps (0: none)")
      ->check(CLI::NonNegativeNumber);
  run_command->callback([run_arguments] { run(*run_arguments); });

  auto json = std::make_shared<bool>(false);
  CLI::App* models = app.add_subcommand("models", "List the models with their parameters");
  models->add_flag("--json", *json, "as JSON");
  models->callback([json] { list_models(*json); });
}

}  // namespace softbench::harness
