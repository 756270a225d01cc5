// SPDX-License-Identifier: MIT
#pragma once

#include <CLI/CLI.hpp>

namespace softbench::harness {

/// `softbench mesh liver --out DIR` and `softbench mesh tetrahedralize SURFACE --out DIR`.
/// Compiled into the executable only: it links meshgen (TetGen, AGPL; CGAL, GPL), which no
/// library a user links to add a model may pull in.
void add_mesh_generation_commands(CLI::App& mesh);

}  // namespace softbench::harness
