// SPDX-License-Identifier: MIT
// Fuzzes STL (read_stl): binary (told by its size) and ASCII, then the vertex welding.
#include "fuzz/fuzz_support.h"
#include "geometry/mesh_io.h"

#include <cstddef>
#include <cstdint>

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  softbench::fuzz::fuzz_mesh_reader(softbench::fuzz::as_text(data, size), ".stl",
                                    [](const std::filesystem::path& path) { return softbench::read_stl(path); });
  return 0;
}
