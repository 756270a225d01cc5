// SPDX-License-Identifier: MIT
// `softbench snapshot SCENE --model NAME [--model NAME ...] [--at T ...] [--out FILE.png]`.
#include "harness/cli/cli_options.h"
#include "harness/cli/commands.h"
#include "geometry/input_error.h"
#include "harness/report/pictures.h"
#include "harness/run/accuracy.h"
#include "harness/run/runner.h"

#include <algorithm>
#include <cmath>
#include <iomanip>
#include <iostream>
#include <memory>
#include <sstream>
#include <string>
#include <vector>

namespace softbench::harness {
namespace {

struct SnapshotArguments {
  std::string scene;
  std::vector<std::string> models;
  std::vector<double> times;
  std::string out;
  std::string mesh;
  int width = 480;
  int height = 360;
};

std::string seconds(double t) {
  std::ostringstream text;
  text << std::setprecision(4) << t << " s";
  return text.str();
}

void snapshot(const SnapshotArguments& arguments) {
  const scenes::Scene scene = load_scene_with_mesh(arguments.scene, arguments.mesh);
  std::vector<double> times = arguments.times.empty() ? picture_times(scene) : arguments.times;
  for (const double t : times) {
    if (!(t >= 0.0 && t <= scene.duration)) {
      throw InputError("--at " + std::to_string(t) + ": outside the scene's time 0 .. "
                       + std::to_string(scene.duration) + " s");
    }
  }
  std::sort(times.begin(), times.end());
  const std::filesystem::path out =
      arguments.out.empty()
          ? std::filesystem::path("out") / (folder_name(scene.name) + "_snapshot.png")
          : std::filesystem::path(arguments.out);
  check_writable_file(out, "--out");
  if (!pictures_available()) {
    throw InputError("softbench snapshot: this build draws no pictures (configured without "
                     "SOFTBENCH_WITH_RENDER)");
  }
  const SceneMesh mesh = read_scene_mesh(scene);
  RunOptions options;
  options.models = arguments.models;
  options.picture_times = times;
  options.progress = &std::cerr;
  options.live_progress = live_progress();
  std::vector<std::vector<Picture>> rows;
  for (const ModelRun& run : run_scene(scene, mesh, options)) {
    std::vector<Picture>& row = rows.emplace_back();
    for (std::size_t k = 0; k < times.size(); ++k) {
      // A run that blew up before this time has no picture: the tile stays blank.
      row.push_back(k < run.pictures.size()
                        ? Picture{times[k], run.pictures[k].positions}
                        : Picture{times[k], Eigen::Matrix3Xd::Constant(3, 1, std::nan(""))});
    }
  }
  write_pictures(out, scene, mesh, rows, arguments.width, arguments.height);
  std::cout << "wrote " << out.string() << ": rows";
  for (const std::string& model : arguments.models) {
    std::cout << " " << model;
  }
  std::cout << "; columns";
  for (const double t : times) {
    std::cout << " " << seconds(t);
  }
  std::cout << "\n";
}

}  // namespace

void add_snapshot_command(CLI::App& app) {
  auto arguments = std::make_shared<SnapshotArguments>();
  CLI::App* command = app.add_subcommand(
      "snapshot",
      "Run the scene through each model and draw the deformed body (and the instrument) at the "
      "given times into one PNG, offscreen: a row per model, a column per time, every tile from "
      "the same camera; the tissue in its colour, the surface of inverted tets in yellow. A "
      "model that blew up before a time leaves its tile blank");
  add_scene_argument(*command, arguments->scene);
  add_model_option(*command, arguments->models, "model to draw (repeatable)");
  command->get_option("--model")->required();
  command->add_option("--at", arguments->times,
                      "scene time to draw, s (repeatable; default: when the instrument or grasp "
                      "lets go, and the scene's end)");
  command->add_option("--out", arguments->out, "the PNG to write (default: out/<scene>_snapshot.png)");
  command->add_option("--width", arguments->width, "tile width in pixels (default 480)")
      ->check(CLI::Range(16, 4096));
  command->add_option("--height", arguments->height, "tile height in pixels (default 360)")
      ->check(CLI::Range(16, 4096));
  add_mesh_option(*command, arguments->mesh);
  command->callback([arguments] { snapshot(*arguments); });
}

}  // namespace softbench::harness
