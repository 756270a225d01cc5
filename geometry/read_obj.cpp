// SPDX-License-Identifier: MIT
#include "geometry/mesh_builder.h"
#include "geometry/mesh_io.h"
#include "geometry/text_tokenizer.h"

#include <algorithm>
#include <array>
#include <limits>
#include <string>
#include <string_view>
#include <vector>

namespace softbench {
namespace {

// Statements that carry no vertex or face: texture and normal data, materials, grouping, display
// hints, and lines/points (a polyline such as a tool's centreline has no triangles).
bool is_ignored_statement(std::string_view keyword) {
  static constexpr std::array<std::string_view, 21> kIgnored = {
      "vt",       "vn",     "vp",     "mtllib",     "usemtl",    "o",     "g",
      "s",        "l",      "p",      "mg",         "lod",       "bevel", "c_interp",
      "d_interp", "maplib", "usemap", "shadow_obj", "trace_obj", "ctech", "stech"};
  return std::find(kIgnored.begin(), kIgnored.end(), keyword) != kIgnored.end();
}

class ObjReader {
 public:
  explicit ObjReader(const std::filesystem::path& path) : text_(path, '#') {}

  MeshData read() {
    while (const std::optional<TextLine> line = text_.next_line()) {
      const std::string_view keyword = (*line)[0];
      if (keyword == "v") {
        read_vertex(*line);
      } else if (keyword == "f") {
        read_face(*line);
      } else if (!is_ignored_statement(keyword)) {
        text_.fail(concat("unsupported OBJ statement ", quoted_token(keyword),
                          " (expected v, f, or one of vt vn vp mtllib usemtl o g s l)"));
      }
    }
    if (largest_index_ > mesh_.vertex_count()) {
      text_.fail_at(largest_index_line_,
                    concat("face index ", largest_index_, " out of range (file has ",
                           mesh_.vertex_count(), " vertices)"));
    }
    return mesh_.finish(text_.file());
  }

 private:
  void read_vertex(const TextLine& line) {
    if (line.size() < 4) {
      text_.fail(concat("expected 'v x y z', found ", line.size() - 1, " coordinates"));
    }
    const int number = mesh_.vertex_count() + 1;  // OBJ numbers vertices from 1
    mesh_.add_vertex(text_.parse_coordinate(line[1], "vertex", number),
                     text_.parse_coordinate(line[2], "vertex", number),
                     text_.parse_coordinate(line[3], "vertex", number));
  }

  // `f 3`, `f 3/1`, `f 3//2`, `f 3/1/2` name vertex 3 and `f -1` the last vertex so far: only the
  // part before the first '/' matters here.
  int vertex_index(std::string_view corner, int line_number) {
    const std::string_view position = corner.substr(0, corner.find('/'));
    const std::int64_t index = text_.parse_integer(position, "face index");
    const int vertices_so_far = mesh_.vertex_count();
    if (index == 0) {
      text_.fail("face index 0 is invalid (OBJ indices start at 1)");
    }
    if (index < 0) {
      // Compared without negating: -index overflows for the smallest int64.
      if (index < -static_cast<std::int64_t>(vertices_so_far)) {
        text_.fail(concat("relative face index ", index, " reaches before the first vertex (",
                          vertices_so_far, " vertices so far)"));
      }
      return vertices_so_far + static_cast<int>(index);
    }
    if (index > std::numeric_limits<int>::max()) {
      text_.fail(concat("face index ", index, " is out of range"));
    }
    if (index > largest_index_) {
      largest_index_ = static_cast<int>(index);
      largest_index_line_ = line_number;
    }
    return static_cast<int>(index) - 1;
  }

  void read_face(const TextLine& line) {
    if (line.size() < 4) {
      text_.fail(concat("a face needs at least 3 vertices, found ", line.size() - 1));
    }
    polygon_.clear();
    for (std::size_t i = 1; i < line.size(); ++i) {
      polygon_.push_back(vertex_index(line[i], line.number));
    }
    // Fan triangulation: exact for the convex polygons OBJ exporters write.
    for (std::size_t i = 1; i + 1 < polygon_.size(); ++i) {
      mesh_.add_triangle(polygon_[0], polygon_[i], polygon_[i + 1]);
    }
  }

  TextTokenizer text_;
  MeshBuilder mesh_;
  // Positive indices may refer to vertices defined later in the file, so they are checked once
  // all vertices are known: the largest one and its line are all that check needs.
  int largest_index_ = 0;
  int largest_index_line_ = 0;
  std::vector<int> polygon_;  // reused for every face
};

}  // namespace

MeshData read_obj(const std::filesystem::path& path) {
  return ObjReader(path).read();
}

}  // namespace softbench
