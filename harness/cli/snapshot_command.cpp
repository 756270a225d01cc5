// SPDX-License-Identifier: MIT
// `softbench snapshot SCENE --model NAME [--model NAME ...] [--at T ...] [--out FILE.png]`.
#include "harness/cli/cli_options.h"
#include "harness/cli/commands.h"
#include "geometry/input_error.h"
#include "harness/report/pictures.h"
#include "harness/run/accuracy.h"
#include "harness/run/runner.h"

#include <algorithm>
#include <iomanip>
#include <iostream>
#include <memory>
#include <sstream>
#include <string>
#include <vector>

namespace softbench::harness {
namespace {

/// The most pixels one snapshot may hold (256 MB of RGBA): e.g. 16 tiles of 2048 x 2048.
constexpr double kMaxPixels = 64.0 * 1024 * 1024;

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
  // One picture holds every tile: bound its pixels before anything runs.
  const double pixels = static_cast<double>(arguments.width) * arguments.height
                        * static_cast<double>(times.size()) * static_cast<double>(arguments.models.size());
  if (pixels > kMaxPixels) {
    throw InputError("--width x --height x --at x --model: " + std::to_string(pixels)
                     + " pixels, over the limit of " + std::to_string(kMaxPixels));
  }
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
  write_pictures(out, scene, mesh, run_scene(scene, mesh, options), times.size(), arguments.width,
                 arguments.height);
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
  command->add_option("--width", arguments->width, "tile width in pixels (default 480, at most 2048)")
      ->check(CLI::Range(16, 2048));
  command->add_option("--height", arguments->height, "tile height in pixels (default 360, at most 2048)")
      ->check(CLI::Range(16, 2048));
  add_mesh_option(*command, arguments->mesh);
  command->callback([arguments] { snapshot(*arguments); });
}

}  // namespace softbench::harness
