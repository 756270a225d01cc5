// SPDX-License-Identifier: MIT
#include "geometry/input_error.h"
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

struct ObjReader {
  TextTokenizer& text;
  MeshBuilder mesh;
  // Positive indices may in principle refer forward, so they are checked against the final vertex
  // count; the largest one and its line are enough to report the first offender's kind.
  int largest_index = 0;
  int largest_index_line = 0;
  std::vector<int> polygon;

  void read_vertex(const TextLine& line) {
    if (line.size() < 4) {
      text.fail(concat("expected 'v x y z', found ", line.size() - 1, " coordinates"));
    }
    const std::string owner = concat("vertex ", mesh.vertex_count() + 1);
    mesh.add_vertex(text.parse_coordinate(line[1], owner), text.parse_coordinate(line[2], owner),
                    text.parse_coordinate(line[3], owner));
  }

  // `f 3`, `f 3/1`, `f 3//2`, `f 3/1/2` and `f -1` all name vertex 3 (or the last one): only the
  // part before the first '/' matters here.
  int vertex_index(std::string_view corner, int line_number) {
    const std::string_view position = corner.substr(0, corner.find('/'));
    const std::int64_t index = text.parse_integer(position, "face index");
    const int vertices_so_far = mesh.vertex_count();
    if (index == 0) {
      text.fail("face index 0 is invalid (OBJ indices start at 1)");
    }
    if (index < 0) {
      if (-index > vertices_so_far) {
        text.fail(concat("relative face index ", index, " reaches before the first vertex (",
                         vertices_so_far, " vertices so far)"));
      }
      return vertices_so_far + static_cast<int>(index);
    }
    if (index > std::numeric_limits<int>::max()) {
      text.fail(concat("face index ", index, " is out of range"));
    }
    if (index > largest_index) {
      largest_index = static_cast<int>(index);
      largest_index_line = line_number;
    }
    return static_cast<int>(index) - 1;
  }

  void read_face(const TextLine& line) {
    if (line.size() < 4) {
      text.fail(concat("a face needs at least 3 vertices, found ", line.size() - 1));
    }
    polygon.clear();
    for (std::size_t i = 1; i < line.size(); ++i) {
      polygon.push_back(vertex_index(line[i], line.number));
    }
    // Fan triangulation: exact for the convex polygons OBJ exporters write.
    for (std::size_t i = 1; i + 1 < polygon.size(); ++i) {
      mesh.add_triangle(polygon[0], polygon[i], polygon[i + 1]);
    }
  }
};

}  // namespace

MeshData read_obj(const std::filesystem::path& path) {
  TextTokenizer text(path, '#');
  ObjReader reader{text, {}, 0, 0, {}};
  while (const std::optional<TextLine> line = text.next_line()) {
    const std::string_view keyword = (*line)[0];
    if (keyword == "v") {
      reader.read_vertex(*line);
    } else if (keyword == "f") {
      reader.read_face(*line);
    } else if (!is_ignored_statement(keyword)) {
      text.fail(concat("unsupported OBJ statement ", quoted_token(keyword),
                       " (expected v, f, or one of vt vn vp mtllib usemtl o g s l)"));
    }
  }
  if (reader.largest_index > reader.mesh.vertex_count()) {
    text.fail_at(reader.largest_index_line,
                 concat("face index ", reader.largest_index, " out of range (file has ",
                        reader.mesh.vertex_count(), " vertices)"));
  }
  return reader.mesh.finish(path.string());
}

}  // namespace softbench
