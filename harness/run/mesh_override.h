// SPDX-License-Identifier: MIT
#pragma once

#include "scenes/scene.h"

#include <filesystem>

namespace softbench::harness {

/// `--mesh PATH` of `run` and `compare`: replaces the scene's mesh with `mesh` (resolved against
/// the working directory, as a command-line path is), keeping everything else, e.g. to run
/// scenes/sofa_liver.json on SOFA's own liver.msh. Throws InputError when the file does not
/// exist. The scene's regions are not re-read here: the runner checks them on the new mesh and
/// names it (a fixed vertex index out of range, a box that selects nothing).
void override_mesh(scenes::Scene& scene, const std::filesystem::path& mesh);

}  // namespace softbench::harness
