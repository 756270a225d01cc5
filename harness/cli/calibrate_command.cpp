// SPDX-License-Identifier: MIT
// `softbench calibrate SCENE --model NAME [--against MODEL] [--write OUT.json]`.
#include "geometry/atomic_file.h"
#include "geometry/input_error.h"
#include "harness/calibrate/calibration.h"
#include "harness/cli/cli_options.h"
#include "harness/cli/commands.h"
#include "models/json_file.h"
#include "scenes/scene.h"

#include <filesystem>
#include <iomanip>
#include <iostream>
#include <memory>
#include <sstream>
#include <string>

namespace softbench::harness {
namespace {

std::string percent(double fraction) {
  std::ostringstream out;
  out << std::showpos << std::fixed << std::setprecision(1) << 100.0 * fraction << "%";
  return out.str();
}

void print(const Calibration& c, const scenes::Scene& scene, std::ostream& out) {
  out << "# " << c.model << " fitted to " << c.against << " on " << scene.name << " (dt "
      << scene.dt << " s)" << (c.cached ? ", from the cache" : "") << "\n";
  out << "fitted:";
  for (const auto& [name, value] : c.values.items()) {
    out << " " << name << " = " << value.get<double>();
  }
  out << "\n";
  out << "target | " << c.against << " | " << c.model << " | error\n";
  out << "sag | " << format_cm(c.reference.sag.sag) << " | " << format_cm(c.fitted.sag.sag)
      << " | " << percent(c.errors[0]) << "\n";
  for (std::size_t i = 0; i < c.reference.forces.size(); ++i) {
    out << c.targets[i + 1] << " | " << c.reference.forces[i] << " N | " << c.fitted.forces[i]
        << " N | " << percent(c.errors[i + 1]) << "\n";
  }
  if (!c.fitted.implausible.empty()) {
    out << "no candidate in the range stayed a tissue; the best is not one either: "
        << c.fitted.implausible << "\n";
  }
  out << "calibration: " << c.evaluations << " runs in " << std::fixed << std::setprecision(1)
      << c.seconds << " s (the reference's runs: " << c.reference_seconds << " s, cached)\n";
  out.unsetf(std::ios::fixed);
  out << "\"" << c.model << "\": " << c.params.dump() << "\n";
}

}  // namespace

void add_calibrate_command(CLI::App& app) {
  struct Arguments {
    std::string scene;
    std::string model;
    std::string against = "neo_hookean";
    std::string write;
  };
  auto arguments = std::make_shared<Arguments>();
  CLI::App* command = app.add_subcommand(
      "calibrate",
      "Fit a model whose stiffness is not a material constant (mass_spring, shape_matching, "
      "bullet_softbody) to the reference's static sag and press forces on the scene's tissue; "
      "print the block to paste");
  add_scene_argument(*command, arguments->scene);
  command->add_option("--model", arguments->model, "the model to calibrate")->required();
  command->add_option("--against", arguments->against,
                      "the reference it is fitted to (neo_hookean, corotational_fem)");
  command->add_option("--write", arguments->write,
                      "write a copy of the scene with the fitted block to this file");
  command->callback([arguments] {
    const scenes::Scene scene = scenes::load_scene(arguments->scene);
    if (!calibratable(arguments->model)) {
      throw InputError("calibrate: --model " + arguments->model
                       + ": its stiffness follows the material; nothing to fit");
    }
    CalibrationOptions options;
    options.against = arguments->against;
    options.progress = &std::cerr;
    const SceneMesh mesh = read_scene_mesh(scene);
    // Check the output can be written before the runs, not after.
    if (!arguments->write.empty()) {
      check_writable_file(arguments->write, "--write");
    }
    const Calibration calibration = calibrate(scene, mesh, arguments->model, options);
    print(calibration, scene, std::cout);
    if (!arguments->write.empty()) {
      const std::filesystem::path out = arguments->write;
      const nlohmann::json json = scene_with_block(
          read_json_file(scene.source), scene.source,
          out.parent_path().empty() ? std::filesystem::path(".") : out.parent_path(),
          arguments->model, calibration.params);
      const std::string text = json.dump(2) + "\n";
      write_file_atomically(out, [&](std::ostream& stream) { stream << text; });
      std::cout << "wrote " << out.string() << "\n";
    }
  });
}

}  // namespace softbench::harness
