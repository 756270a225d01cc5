// SPDX-License-Identifier: MIT
#pragma once

#include <filesystem>
#include <functional>
#include <ostream>

namespace softbench {

/// Writes `path` through `write_content`: into a temporary file in the same directory, then a
/// rename over `path`, so a reader (ParaView polling a frame, a second run) never sees a
/// half-written file and a failed write leaves any previous file intact. Throws InputError
/// "<path>: cannot write (<reason>)" when the directory or the stream fails.
void write_file_atomically(const std::filesystem::path& path,
                           const std::function<void(std::ostream&)>& write_content);

}  // namespace softbench
