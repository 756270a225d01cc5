// SPDX-License-Identifier: MIT
// Fuzzes legacy VTK (read_vtk): ASCII and BINARY, POLYDATA and UNSTRUCTURED_GRID, versions 2.0 to 5.1.
#include "fuzz/fuzz_support.h"
#include "geometry/mesh_io.h"

#include <cstddef>
#include <cstdint>

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  softbench::fuzz::fuzz_mesh_reader(softbench::fuzz::as_text(data, size), ".vtk",
                                    softbench::read_vtk);
  return 0;
}
