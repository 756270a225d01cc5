// SPDX-License-Identifier: MIT
#pragma once

#include <filesystem>
#include <string_view>

namespace softbench::scenes {

/// The folder of meshes the project ships (scenes/data/ in the source tree): the generated
/// liver at three resolutions, its surface, and the instrument.
std::filesystem::path shipped_data_dir();

/// shipped_data_dir() / name; throws InputError when the file is not there.
std::filesystem::path shipped_data_file(std::string_view name);

}  // namespace softbench::scenes
