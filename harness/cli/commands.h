// SPDX-License-Identifier: MIT
// The softbench command line: one add_*_command per command, each in its own file
// (<command>_command.cpp), with the options they share in cli_options.h.
#pragma once

#include <CLI/CLI.hpp>

namespace softbench::harness {

void add_run_command(CLI::App& app);        ///< softbench run
void add_models_command(CLI::App& app);     ///< softbench models
void add_compare_command(CLI::App& app);    ///< softbench compare
void add_sweep_command(CLI::App& app);      ///< softbench sweep
void add_merge_command(CLI::App& app);      ///< softbench merge
void add_recommend_command(CLI::App& app);  ///< softbench recommend
void add_stability_command(CLI::App& app);  ///< softbench stability
void add_calibrate_command(CLI::App& app);  ///< softbench calibrate
void add_verify_command(CLI::App& app);     ///< softbench verify
void add_soak_command(CLI::App& app);       ///< softbench soak
void add_snapshot_command(CLI::App& app);   ///< softbench snapshot
void add_view_command(CLI::App& app);       ///< softbench view
void add_mesh_command(CLI::App& app);       ///< softbench mesh info (and liver, tetrahedralize)
void add_mesh_generation_commands(CLI::App& mesh);  ///< softbench mesh liver, mesh tetrahedralize

}  // namespace softbench::harness
