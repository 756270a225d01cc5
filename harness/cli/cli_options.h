// SPDX-License-Identifier: MIT
// Options several commands share, declared once so they read and behave the same everywhere.
#pragma once

#include "harness/format.h"
#include "scenes/scene.h"

#include <CLI/CLI.hpp>

#include <filesystem>
#include <string>
#include <vector>

namespace softbench::harness {

/// The positional scene file.
void add_scene_argument(CLI::App& command, std::string& scene);
/// `--model NAME`, repeatable, one name per flag (a scene after it stays a scene).
void add_model_option(CLI::App& command,
                      std::vector<std::string>& models,
                      const std::string& default_text);
/// `--out DIR`; `default_text` says what an empty value means.
void add_out_option(CLI::App& command, std::string& out_dir, const std::string& default_text);
/// `--mesh PATH`: replace the scene's mesh.
void add_mesh_option(CLI::App& command, std::string& mesh);
/// `--no-plots`.
void add_no_plots_flag(CLI::App& command, bool& no_plots, const std::string& what_is_written);

/// The scene at `file`, its mesh replaced by `mesh` unless that is empty.
scenes::Scene load_scene_with_mesh(const std::string& file, const std::string& mesh);
/// `given`, else `fallback`.
std::filesystem::path out_dir_or(const std::string& given, const std::filesystem::path& fallback);
/// Throws InputError "OPTION PATH: cannot write (why)" unless a file can be written at `path`
/// (its folder exists or can be made, the path is not a folder): checked before a command runs
/// anything, so a bad output path does not cost the run.
void check_writable_file(const std::filesystem::path& path, const std::string& option);
/// Whether progress may rewrite its line (stderr is a terminal).
bool live_progress();

}  // namespace softbench::harness
