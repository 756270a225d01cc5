// SPDX-License-Identifier: MIT
#include "geometry/mesh_builder.h"
#include "geometry/mesh_io.h"
#include "geometry/tetgen_files.h"
#include "geometry/text_tokenizer.h"

#include <array>
#include <functional>
#include <string>
#include <string_view>

// TetGen's .node/.ele/.face files. Each starts with a header line of counts, then one line per
// item starting with its index; '#' starts a comment. The first point's index (0 or 1) sets the
// numbering of every vertex reference, as in TetGen itself.
namespace softbench {
namespace {

std::filesystem::path tetgen_base(const std::filesystem::path& path) {
  const std::string extension = lowercase_extension(path);
  if (extension == ".node" || extension == ".ele" || extension == ".face") {
    return std::filesystem::path(path).replace_extension();
  }
  return path;
}

// The header's integer fields; TetGen lets trailing ones default, and so does this.
template <std::size_t N>
std::array<int, N> read_header(TextTokenizer& text,
                               std::string_view layout,
                               const std::array<int, N>& defaults) {
  const TextLine header = text.expect_line(concat("header '", layout, "'"));
  if (header.size() > N) {
    text.fail(concat("expected at most ", N, " values (", layout, "), found ", header.size()));
  }
  std::array<int, N> fields = defaults;
  for (std::size_t i = 0; i < header.size(); ++i) {
    fields[i] = text.parse_count(header[i], concat("header field ", i + 1));
  }
  return fields;
}

// Reads `count` item lines of `tokens` values each, checking that the leading indices run
// consecutively from 0 or 1. Returns that first index (0 when there are no items).
int read_items(TextTokenizer& text,
               int count,
               std::size_t tokens,
               std::string_view item,
               std::string_view layout,
               const std::function<void(const TextLine&, std::int64_t index)>& read_item) {
  text.check_count_fits(count, concat(item, "s"));
  const std::string index_name = concat(item, " index");
  int first_index = 0;
  for (int i = 0; i < count; ++i) {
    std::optional<TextLine> line = text.next_line();
    if (!line) {
      text.fail(concat("expected ", count, " ", item, "s, found ", i, " before end of file"));
    }
    text.require_tokens(*line, tokens, layout);
    const std::int64_t index = text.parse_integer((*line)[0], index_name);
    if (i == 0) {
      if (index != 0 && index != 1) {
        text.fail(concat("first ", item, " index must be 0 or 1, found ", index));
      }
      first_index = static_cast<int>(index);
    } else if (index != first_index + i) {
      text.fail(concat("expected ", item, " index ", first_index + i, ", found ", index,
                       " (indices must be consecutive)"));
    }
    read_item(*line, index);
  }
  if (const std::optional<TextLine> extra = text.next_line()) {
    text.fail(concat("expected ", count, " ", item,
                     "s as the header says, found more: ", quoted_token((*extra)[0])));
  }
  return first_index;
}

struct VertexNumbering {
  std::string node_file;
  int first_index = 0;
  int count = 0;
};

int vertex_reference(const TextTokenizer& text,
                     std::string_view token,
                     const VertexNumbering& numbering) {
  const std::int64_t index = text.parse_integer(token, "vertex index");
  if (index < numbering.first_index || index >= numbering.first_index + numbering.count) {
    text.fail(concat("vertex index ", index, " out of range (", numbering.node_file, " has ",
                     numbering.count, " points, numbered from ", numbering.first_index, ")"));
  }
  return static_cast<int>(index) - numbering.first_index;
}

// <#points> <dimension (3)> <#attributes> <#boundary markers (0 or 1)>
// <index> <x> <y> <z> [attributes] [boundary marker]
VertexNumbering read_node_file(const std::filesystem::path& path, MeshBuilder& mesh) {
  TextTokenizer text(path, '#');
  const auto [count, dimension, attributes, markers] =
      read_header<4>(text, "#points dimension #attributes #boundary-markers", {0, 3, 0, 0});
  if (dimension != 3) {
    text.fail(concat("dimension ", dimension, " is not supported; expected 3"));
  }
  if (markers > 1) {
    text.fail(concat("number of boundary markers must be 0 or 1, found ", markers));
  }
  const auto add_point = [&](const TextLine& line, std::int64_t index) {
    mesh.add_vertex(text.parse_coordinate(line[1], "point", index),
                    text.parse_coordinate(line[2], "point", index),
                    text.parse_coordinate(line[3], "point", index));
  };
  const std::size_t tokens =
      4 + static_cast<std::size_t>(attributes) + static_cast<std::size_t>(markers);
  const int first_index =
      read_items(text, count, tokens, "point", "index x y z, attributes, marker", add_point);
  return {path.filename().string(), first_index, count};
}

// <#tetrahedra> <nodes per tet (4)> <#attributes>
// <index> <n1> <n2> <n3> <n4> [attributes]
void read_ele_file(const std::filesystem::path& path,
                   const VertexNumbering& numbering,
                   MeshBuilder& mesh) {
  TextTokenizer text(path, '#');
  const auto [count, nodes_per_tet, attributes] =
      read_header<3>(text, "#tetrahedra nodes-per-tet #attributes", {0, 4, 0});
  if (nodes_per_tet == 10) {
    text.fail("second-order tetrahedra (10 nodes per tet) are not supported; expected 4");
  }
  if (nodes_per_tet != 4) {
    text.fail(concat("expected 4 nodes per tetrahedron, found ", nodes_per_tet));
  }
  const auto add_tet = [&](const TextLine& line, std::int64_t) {
    mesh.add_tetrahedron(
        vertex_reference(text, line[1], numbering), vertex_reference(text, line[2], numbering),
        vertex_reference(text, line[3], numbering), vertex_reference(text, line[4], numbering));
  };
  read_items(text, count, 5 + static_cast<std::size_t>(attributes), "tetrahedron",
             "index n1 n2 n3 n4, attributes", add_tet);
}

// <#faces> <#boundary markers (0 or 1)>
// <index> <n1> <n2> <n3> [boundary marker]
void read_face_file(const std::filesystem::path& path,
                    const VertexNumbering& numbering,
                    MeshBuilder& mesh) {
  TextTokenizer text(path, '#');
  const auto [count, markers] = read_header<2>(text, "#faces #boundary-markers", {0, 0});
  if (markers > 1) {
    text.fail(concat("number of boundary markers must be 0 or 1, found ", markers));
  }
  const auto add_face = [&](const TextLine& line, std::int64_t) {
    mesh.add_triangle(vertex_reference(text, line[1], numbering),
                      vertex_reference(text, line[2], numbering),
                      vertex_reference(text, line[3], numbering));
  };
  read_items(text, count, 4 + static_cast<std::size_t>(markers), "face", "index n1 n2 n3, marker",
             add_face);
}

}  // namespace

MeshData read_tetgen(const std::filesystem::path& path) {
  const std::filesystem::path base = tetgen_base(path);
  MeshBuilder mesh;
  const VertexNumbering numbering = read_node_file(tetgen_file(base, ".node"), mesh);
  if (const auto ele = tetgen_file(base, ".ele"); std::filesystem::exists(ele)) {
    read_ele_file(ele, numbering, mesh);
  }
  if (const auto face = tetgen_file(base, ".face"); std::filesystem::exists(face)) {
    read_face_file(face, numbering, mesh);
  }
  return mesh.finish(path.string());
}

}  // namespace softbench
