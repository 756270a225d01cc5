// SPDX-License-Identifier: MIT
// `softbench recommend SCENE [--sweep DIR]`: the cheapest model meeting the scene's requirements.
#include "geometry/input_error.h"
#include "harness/cli/cli_options.h"
#include "harness/cli/commands.h"
#include "harness/cli/sweep_output.h"
#include "harness/sweep/recommend.h"
#include "harness/sweep/sweep.h"
#include "scenes/scene.h"

#include <iostream>
#include <memory>
#include <string>

namespace softbench::harness {
namespace {

void recommend_for(const std::string& scene_file, const std::string& sweep_dir) {
  const scenes::Scene scene = scenes::load_scene(scene_file);
  if (!scene.requirements) {
    throw InputError(scene_file + ": /requirements: missing (say what the scene needs: "
                     "steps_per_second, accuracy, outputs)");
  }
  const std::filesystem::path dir = out_dir_or(sweep_dir, default_sweep_dir(scene.name));
  if (const std::string refusal = ranking_refusal(read_reference_convergence({dir}));
      !refusal.empty()) {
    std::cout << "No recommendation: " << refusal << ".\n";
    return;
  }
  const Recommendation result = recommend(*scene.requirements, read_sweep_runs({dir}));
  std::cout << result.explanation;
}

}  // namespace

void add_recommend_command(CLI::App& app) {
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
