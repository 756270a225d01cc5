// SPDX-License-Identifier: MIT
// Fuzzes Gmsh MSH (read_msh): versions 1 ($NOD/$ELM), 2.2 and 4.1 ($Nodes/$Elements), sections skipped.
#include "fuzz/fuzz_support.h"
#include "geometry/mesh_io.h"

#include <cstddef>
#include <cstdint>

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  softbench::fuzz::fuzz_mesh_reader(softbench::fuzz::as_text(data, size), ".msh",
                                    softbench::read_msh);
  return 0;
}
