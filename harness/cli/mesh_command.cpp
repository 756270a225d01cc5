// SPDX-License-Identifier: MIT
// `softbench mesh info FILE [--json]`, and with mesh generation built, `mesh liver` and
// `mesh tetrahedralize`.
#include "geometry/input_error.h"
#include "geometry/mesh_io.h"
#include "harness/cli/commands.h"
#include "harness/report/mesh_info.h"

#include <filesystem>
#include <iostream>
#include <memory>
#include <string>

namespace softbench::harness {
namespace {

struct InfoArguments {
  std::string file;
  bool json = false;
};

void run_info(const InfoArguments& arguments) {
  const MeshInfo info = inspect_mesh(read_mesh(arguments.file));
  if (arguments.json) {
    std::cout << to_json(info).dump(2) << "\n";
  } else {
    std::cout << to_text(info);
  }
  if (!info.usable()) {
    throw InputError(arguments.file + ": mesh has errors (listed above)");
  }
}

}  // namespace

void add_mesh_command(CLI::App& app) {
  CLI::App* mesh = app.add_subcommand("mesh", "Inspect, generate and tetrahedralize meshes");
  mesh->require_subcommand(1);

  auto info_arguments = std::make_shared<InfoArguments>();
  CLI::App* info = mesh->add_subcommand(
      "info",
      "Counts, bounding box, volume, quality and problems of a mesh file (.obj .msh "
      ".node/.ele .stl .vtk .vtu)");
  info->add_option("file", info_arguments->file, "mesh file")->required();
  info->add_flag("--json", info_arguments->json, "one JSON object instead of text");
  info->callback([info_arguments] { run_info(*info_arguments); });

#if SOFTBENCH_WITH_MESHGEN
  add_mesh_generation_commands(*mesh);
#endif
}

}  // namespace softbench::harness
