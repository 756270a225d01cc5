// SPDX-License-Identifier: MIT
#include "harness/report/report_files.h"

#include "geometry/atomic_file.h"

#include <ostream>

namespace softbench::harness {

void write_report_files(const std::filesystem::path& out_dir, const std::vector<ReportFile>& files) {
  std::filesystem::create_directories(out_dir);
  for (const auto& [name, text] : files) {
    write_file_atomically(out_dir / name, [&text](std::ostream& out) { out << text; });
  }
}

}  // namespace softbench::harness
