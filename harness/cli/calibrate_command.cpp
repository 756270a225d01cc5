// SPDX-License-Identifier: MIT
// `softbench calibrate SCENE --model bullet_softbody [--tolerance 0.02]`.
#include "geometry/input_error.h"
#include "harness/calibrate/calibration.h"
#include "harness/cli/cli_options.h"
#include "harness/cli/commands.h"
#include "scenes/scene.h"

#include <iostream>
#include <memory>
#include <string>

namespace softbench::harness {

void add_calibrate_command(CLI::App& app) {
  struct Arguments {
    std::string scene;
    std::string model = kCalibratedModel;
    double tolerance = 0.02;
  };
  auto arguments = std::make_shared<Arguments>();
  CLI::App* command = app.add_subcommand(
      "calibrate",
      "Fit bullet_softbody's unitless stiffness so its static sag under the scene's gravity "
      "matches the corotational FEM's at the scene's dt; print the block to paste");
  add_scene_argument(*command, arguments->scene);
  command->add_option("--model", arguments->model, "the model to calibrate (bullet_softbody)");
  command->add_option("--tolerance", arguments->tolerance, "relative sag mismatch accepted")
      ->check(CLI::Range(1e-4, 0.5));
  command->callback([arguments] {
    if (arguments->model != kCalibratedModel) {
      throw InputError("calibrate: --model " + arguments->model + ": only " + kCalibratedModel
                       + " has a stiffness without units to calibrate");
    }
    const scenes::Scene scene = scenes::load_scene(arguments->scene);
    const StiffnessCalibration calibration =
        calibrate_bullet_softbody(scene, arguments->tolerance, &std::cerr);
    std::cout << "# " << scene.name << " at dt = " << scene.dt << " s: " << calibration.against
              << " sags " << format_cm(calibration.reference_sag) << ", " << kCalibratedModel << " "
              << format_cm(calibration.sag) << " (" << calibration.evaluations
              << " runs). Paste into \"models\":\n"
              << "\"" << kCalibratedModel << "\": " << calibration.params.dump() << "\n";
  });
}

}  // namespace softbench::harness
