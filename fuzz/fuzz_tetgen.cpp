// SPDX-License-Identifier: MIT
// Fuzzes TetGen's files (read_tetgen): .node, .ele and .face in one input, split at the marker
// lines "#@ele" and "#@face" (comments to TetGen, so a seed is also three readable files run
// together). What comes before the first marker is the .node file; a file whose marker is
// absent is not there, which read_tetgen allows for .ele and .face.
#include "fuzz/fuzz_support.h"
#include "geometry/mesh_io.h"

#include <algorithm>
#include <array>
#include <cstddef>
#include <cstdint>
#include <string>
#include <string_view>

namespace {

struct Part {
  std::string_view marker;
  std::string extension;
  std::size_t start = std::string_view::npos;  // where its marker line begins
};

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  namespace fuzz = softbench::fuzz;
  const std::string text = fuzz::as_text(data, size);
  const std::string_view input = text;
  std::array<Part, 2> parts = {{{"#@ele\n", ".ele"}, {"#@face\n", ".face"}}};
  for (Part& part : parts) {
    part.start = input.find(part.marker);
  }
  // Each part runs from the end of its marker line to the next marker (or the end).
  const auto end_of = [&](std::size_t from) {
    std::size_t end = input.size();
    for (const Part& other : parts) {
      if (other.start != std::string_view::npos && other.start >= from) {
        end = std::min(end, other.start);
      }
    }
    return end;
  };
  fuzz::write_scratch_file("input.node", input.substr(0, end_of(0)));
  for (const Part& part : parts) {
    if (part.start == std::string_view::npos) {
      fuzz::remove_scratch_file("input" + part.extension);
      continue;
    }
    const std::size_t begin = part.start + part.marker.size();
    fuzz::write_scratch_file("input" + part.extension, input.substr(begin, end_of(begin) - begin));
  }
  const std::filesystem::path node = fuzz::scratch_folder() / "input.node";
  fuzz::read_and_check_mesh((fuzz::scratch_folder() / "input").string(),
                            [&] { return softbench::read_tetgen(node); });
  return 0;
}
