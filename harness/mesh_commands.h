// SPDX-License-Identifier: MIT
#pragma once

#include <CLI/CLI.hpp>

namespace softbench::harness {

/// Adds `softbench mesh info|liver|tetrahedralize` to the CLI. The generation commands exist
/// only in builds with SOFTBENCH_WITH_MESHGEN (they link TetGen and CGAL).
void add_mesh_commands(CLI::App& app);

}  // namespace softbench::harness
