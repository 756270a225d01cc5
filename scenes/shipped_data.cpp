// SPDX-License-Identifier: MIT
#include "scenes/shipped_data.h"

#include "geometry/input_error.h"

#include <string>

namespace softbench::scenes {

std::filesystem::path shipped_data_dir() {
  return SOFTBENCH_SHIPPED_DATA_DIR;
}

std::filesystem::path shipped_data_file(std::string_view name) {
  const std::filesystem::path path = shipped_data_dir() / name;
  if (!std::filesystem::is_regular_file(path)) {
    throw InputError(path.string()
                     + ": shipped mesh not found (regenerate with `softbench mesh liver --out "
                     + shipped_data_dir().string() + "`)");
  }
  return path;
}

}  // namespace softbench::scenes
