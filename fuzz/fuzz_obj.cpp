// SPDX-License-Identifier: MIT
// Fuzzes Wavefront OBJ (read_obj): v and f statements, slash forms, negative indices, the statements it ignores.
#include "fuzz/fuzz_support.h"
#include "geometry/mesh_io.h"

#include <cstddef>
#include <cstdint>

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  softbench::fuzz::fuzz_mesh_reader(softbench::fuzz::as_text(data, size), ".obj",
                                    softbench::read_obj);
  return 0;
}
