// SPDX-License-Identifier: MIT
// `softbench view SCENE [--model NAME] [--model NAME] [--input FILE] [--report FILE]`.
#include "harness/cli/cli_options.h"
#include "harness/cli/commands.h"
#include "geometry/input_error.h"
#include "harness/interrupt.h"
#include "models/model_registry.h"
#include "scenes/shipped_data.h"

#if SOFTBENCH_WITH_VIEWER
#include "harness/run/scene_mesh.h"
#include "viewer/input_script.h"
#include "viewer/viewer_app.h"
#endif

#include <memory>
#include <string>
#include <vector>

namespace softbench::harness {
namespace {

struct ViewArguments {
  std::string scene;
  std::vector<std::string> models;
  std::string input;
  std::string report;
  std::string mesh;
  bool script = false;
  int width = 1280;
  int height = 720;
};

void view(const ViewArguments& arguments) {
#if SOFTBENCH_WITH_VIEWER
  scenes::Scene scene = load_scene_with_mesh(arguments.scene, arguments.mesh);
  std::vector<std::string> models = arguments.models;
  if (models.empty()) {
    models = {"corotational_fem"};
  }
  if (models.size() > 2) {
    throw InputError("--model: at most two, one viewport each (got " +
                     std::to_string(models.size()) + ")");
  }
  for (const std::string& model : models) {
    builtin_models().at(model);  // an unknown name is bad input, named before a window opens
  }
  if (!scene.instrument) {
    // A scene without a tool still gets one for the hand: the shipped probe, which the scene's
    // script never moves (it never starts to act).
    scenes::Instrument probe;
    probe.mesh = scenes::shipped_data_file("instrument_probe.obj");
    probe.path = {scenes::InstrumentKeyframe{}};
    probe.start = scenes::kNever;
    scene.instrument = probe;
  }
  viewer::ViewOptions options;
  options.models = models;
  options.width = arguments.width;
  options.height = arguments.height;
  options.drive = arguments.script ? viewer::Drive::kScript : viewer::Drive::kHand;
  if (!arguments.input.empty()) {
    options.input = viewer::read_input_script(arguments.input);
  }
  if (!arguments.report.empty()) {
    options.report = arguments.report;
    check_writable_file(options.report, "--report");
  }
  const SceneMesh mesh = read_scene_mesh(scene);
  viewer::run_viewer(scene, mesh, options);
  if (interrupt_requested()) {
    throw Interrupted("the window was closed by a signal");
  }
#else
  (void)arguments;
  throw InputError("softbench view: this build has no viewer (configured without "
                   "SOFTBENCH_WITH_VIEWER: install libglfw3-dev and libimgui-dev, reconfigure)");
#endif
}

}  // namespace

void add_view_command(CLI::App& app) {
  auto arguments = std::make_shared<ViewArguments>();
  CLI::App* command = app.add_subcommand(
      "view",
      "The interactive liver: the scene's body in a window, simulated live by each model on a "
      "thread of its own at the scene's dt (two models: two viewports, the same hand on both). "
      "Drag on the body to press it with the scene's instrument (down presses in), G grasps "
      "and a drag up pulls, right drag turns the view, the wheel zooms; the panel picks the "
      "model, edits its parameters, pauses, steps, resets, or plays the scene's script");
  add_scene_argument(*command, arguments->scene);
  add_model_option(*command, arguments->models,
                   "model to show (repeatable, at most two; default corotational_fem)");
  command->add_flag("--script", arguments->script,
                    "start with the scene's scripted instrument instead of the hand");
  command->add_option("--input", arguments->input,
                      "scripted input, replayed as a person's: mouse, keys, screenshots, quit "
                      "(JSON; see docs/viewer.md)");
  command->add_option("--report", arguments->report,
                      "write the frame rate and each model's pace here at the end (JSON)");
  command->add_option("--width", arguments->width, "window width (default 1280)")
      ->check(CLI::Range(320, 4096));
  command->add_option("--height", arguments->height, "window height (default 720)")
      ->check(CLI::Range(240, 4096));
  add_mesh_option(*command, arguments->mesh);
  command->callback([arguments] { view(*arguments); });
}

}  // namespace softbench::harness
