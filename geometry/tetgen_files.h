// SPDX-License-Identifier: MIT
#pragma once

#include <filesystem>

namespace softbench {

/// base + extension, keeping any dots in the base ("mesh.1" + ".node" -> "mesh.1.node", where
/// replace_extension would give "mesh.node").
inline std::filesystem::path tetgen_file(std::filesystem::path base, const char* extension) {
  base += extension;
  return base;
}

}  // namespace softbench
