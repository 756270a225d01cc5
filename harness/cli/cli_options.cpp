// SPDX-License-Identifier: MIT
#include "harness/cli/cli_options.h"

#include "geometry/input_error.h"
#include "harness/run/mesh_override.h"

#include <unistd.h>

#include <cctype>
#include <fstream>
#include <system_error>
#include <cstddef>

namespace softbench::harness {

void add_scene_argument(CLI::App& command, std::string& scene) {
  command.add_option("scene", scene, "scene file (.json)")->required();
}

void add_model_option(CLI::App& command,
                      std::vector<std::string>& models,
                      const std::string& default_text) {
  command.add_option("--model", models, "model to run (repeatable; default: " + default_text + ")")
      ->allow_extra_args(false);
}

void add_out_option(CLI::App& command, std::string& out_dir, const std::string& default_text) {
  command.add_option("--out", out_dir, "output folder (default: " + default_text + ")");
}

void add_mesh_option(CLI::App& command, std::string& mesh) {
  command.add_option("--mesh", mesh,
                     "replace the scene's mesh (e.g. SOFA's liver.msh for scenes/sofa_liver.json)");
}

void add_no_plots_flag(CLI::App& command, bool& no_plots, const std::string& what_is_written) {
  command.add_flag("--no-plots", no_plots, "write " + what_is_written + " only");
}

scenes::Scene load_scene_with_mesh(const std::string& file, const std::string& mesh) {
  scenes::Scene scene = scenes::load_scene(file);
  if (!mesh.empty()) {
    override_mesh(scene, mesh);
  }
  return scene;
}

std::filesystem::path out_dir_or(const std::string& given, const std::filesystem::path& fallback) {
  return given.empty() ? fallback : std::filesystem::path(given);
}

void check_writable_file(const std::filesystem::path& path, const std::string& option) {
  const auto fail = [&](const std::string& why) {
    throw InputError(option + " " + path.string() + ": cannot write (" + why + ")");
  };
  std::error_code error;
  if (std::filesystem::is_directory(path, error)) {
    fail("it is a folder");
  }
  const std::filesystem::path folder = path.parent_path().empty() ? "." : path.parent_path();
  std::filesystem::create_directories(folder, error);
  if (!std::filesystem::is_directory(folder, error)) {
    fail(folder.string() + " is not a folder");
  }
  // A probe file beside it, removed at once: permissions, a read-only file system.
  const std::filesystem::path probe =
      folder / (".softbench-probe-" + std::to_string(static_cast<long>(::getpid())));
  {
    std::ofstream out(probe);
    if (!out) {
      fail("no permission to create files in " + folder.string());
    }
  }
  std::filesystem::remove(probe, error);
}

bool live_progress() {
  return ::isatty(STDERR_FILENO) != 0;
}

}  // namespace softbench::harness
