// SPDX-License-Identifier: MIT
// A report is a few text files (a JSON for scripts, a Markdown for people) written side by side.
#pragma once

#include <filesystem>
#include <string>
#include <utility>
#include <vector>

namespace softbench::harness {

/// One file of a report: its name in the output folder and its whole text.
using ReportFile = std::pair<std::string, std::string>;

/// Writes every file into `out_dir` (made if missing), each atomically (a temporary renamed
/// into place). Every text is made before the first file is written, by the caller, so a report
/// that fails to render writes none; the folder lands as one unit through StagedFolder.
void write_report_files(const std::filesystem::path& out_dir, const std::vector<ReportFile>& files);

}  // namespace softbench::harness
