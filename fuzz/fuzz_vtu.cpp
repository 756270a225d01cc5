// SPDX-License-Identifier: MIT
// Fuzzes VTK XML UnstructuredGrid (read_vtu): the tag scanner, the Piece sizes, ASCII DataArrays.
#include "fuzz/fuzz_support.h"
#include "geometry/mesh_io.h"

#include <cstddef>
#include <cstdint>

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  softbench::fuzz::fuzz_mesh_reader(softbench::fuzz::as_text(data, size), ".vtu",
                                    softbench::read_vtu);
  return 0;
}
