// SPDX-License-Identifier: MIT
#include "geometry/mesh_builder.h"
#include "geometry/mesh_io.h"
#include "geometry/text_tokenizer.h"

#include <algorithm>
#include <array>
#include <cctype>
#include <string>
#include <string_view>
#include <unordered_map>
#include <vector>

// Gmsh MSH, ASCII. Versions 1 and 2 list one node or element per line; version 4.1 groups them in
// entity blocks. All three share the node-tag remapping and the element-type table below.
namespace softbench {
namespace {

enum class MshVersion { kV1, kV2, kV4 };

struct ElementKind {
  int type = 0;
  int nodes = 0;
  bool kept = false;  ///< points and lines are skipped without a word
};

// Gmsh element types softbench understands: linear triangles and tets are kept, points and lines
// (boundary curves, marker points) are skipped. Anything else is an error naming the type.
constexpr std::array<ElementKind, 4> kElementKinds = {{
    {1, 2, false},  // 2-node line
    {2, 3, true},   // 3-node triangle
    {4, 4, true},   // 4-node tetrahedron
    {15, 1, false}  // 1-node point
}};

std::string element_type_name(std::int64_t type) {
  switch (type) {
    case 3:
      return " (4-node quadrangle)";
    case 5:
      return " (8-node hexahedron)";
    case 6:
      return " (6-node prism)";
    case 7:
      return " (5-node pyramid)";
    case 8:
      return " (3-node second-order line)";
    case 9:
      return " (6-node second-order triangle)";
    case 11:
      return " (10-node second-order tetrahedron)";
    default:
      return "";
  }
}

bool equals_ignoring_case(std::string_view a, std::string_view b) {
  return a.size() == b.size() && std::equal(a.begin(), a.end(), b.begin(), [](char x, char y) {
           return std::tolower(static_cast<unsigned char>(x))
                  == std::tolower(static_cast<unsigned char>(y));
         });
}

// "$Nodes" ends at "$EndNodes", "$NOD" (MSH 1) at "$ENDNOD".
bool ends_section(std::string_view token, std::string_view section) {
  return token.size() == section.size() + 3 && equals_ignoring_case(token.substr(0, 4), "$End")
         && equals_ignoring_case(token.substr(4), section.substr(1));
}

class MshReader {
 public:
  explicit MshReader(const std::filesystem::path& path) : text_(path) {}

  MeshData read() {
    const std::optional<TextLine> first = text_.next_line();
    if (!first) {
      text_.fail("empty file; expected $MeshFormat (MSH 2.2, 4.1) or $NOD (MSH 1)");
    }
    if ((*first)[0] == "$NOD") {
      version_ = MshVersion::kV1;
      read_sections(*first);
    } else if ((*first)[0] == "$MeshFormat") {
      read_format();
      if (std::optional<TextLine> next = text_.next_line()) {
        read_sections(*next);
      }
    } else {
      text_.fail(
          concat("expected $MeshFormat (MSH 2.2, 4.1) or $NOD (MSH 1) at the start of a Gmsh file, "
                 "found ",
                 quoted_token((*first)[0])));
    }
    if (!nodes_read_) {
      text_.fail(concat("no ", nodes_section(), " section in the file"));
    }
    return mesh_.finish(text_.file());
  }

 private:
  const char* nodes_section() const { return version_ == MshVersion::kV1 ? "$NOD" : "$Nodes"; }
  const char* elements_section() const {
    return version_ == MshVersion::kV1 ? "$ELM" : "$Elements";
  }

  void read_format() {
    const TextLine format = text_.expect_line("'version file-type data-size'");
    text_.require_tokens(format, 3, "version file-type data-size");
    const std::string_view version = format[0];
    if (format[1] != "0") {
      text_.fail(
          concat("binary MSH not supported (file-type ", format[1], "); save the mesh as ASCII"));
    }
    if (version == "2" || version == "2.0" || version == "2.1" || version == "2.2") {
      version_ = MshVersion::kV2;
    } else if (version == "4.1") {
      version_ = MshVersion::kV4;
    } else {
      text_.fail(
          concat("unsupported MSH version ", quoted_token(version), " (expected 1, 2.2 or 4.1)"));
    }
    const TextLine end = text_.expect_line("$EndMeshFormat");
    if (end[0] != "$EndMeshFormat") {
      text_.fail(concat("expected $EndMeshFormat, found ", quoted_token(end[0])));
    }
  }

  void read_sections(TextLine header) {
    while (true) {
      const std::string_view name = header[0];
      if (name.empty() || name[0] != '$') {
        text_.fail(concat("expected a section header such as ", nodes_section(), ", found ",
                          quoted_token(name)));
      }
      if (name == nodes_section()) {
        read_nodes();
      } else if (name == elements_section()) {
        read_elements();
      } else {
        skip_section(name);
      }
      std::optional<TextLine> next = text_.next_line();
      if (!next) {
        return;
      }
      header = std::move(*next);
    }
  }

  // $PhysicalNames, $Entities, $NodeData, ... carry nothing softbench uses.
  void skip_section(std::string_view name) {
    const int start = text_.line_number();
    while (const std::optional<TextLine> line = text_.next_line()) {
      if (ends_section((*line)[0], name)) {
        return;
      }
    }
    text_.fail_at(start,
                  concat("section ", name, " has no matching end before the end of the file"));
  }

  // The next line of a section that should hold `found` + 1 of `expected` items, with the count
  // in the message when the section or the file ends early.
  TextLine item_line(std::int64_t found,
                     std::int64_t expected,
                     std::string_view items,
                     std::string_view section) {
    std::optional<TextLine> line = text_.next_line();
    if (!line || (*line)[0].front() == '$') {
      text_.fail(concat("expected ", expected, " ", items, " in ", section, ", found ", found,
                        " before ", line ? (*line)[0] : "end of file"));
    }
    return std::move(*line);
  }

  void expect_section_end(std::string_view section, std::int64_t count, std::string_view items) {
    const TextLine end = text_.expect_line(concat("end of ", section));
    if (!ends_section(end[0], section)) {
      text_.fail(concat("expected the end of ", section, " after ", count, " ", items, ", found ",
                        quoted_token(end[0])));
    }
  }

  std::int64_t read_count(std::size_t tokens,
                          std::string_view layout,
                          std::string_view items,
                          std::size_t count_token) {
    const TextLine line = text_.expect_line(layout);
    text_.require_tokens(line, tokens, layout);
    const int count = text_.parse_count(line[count_token], concat("number of ", items));
    text_.check_count_fits(count, items);
    return count;
  }

  void add_node(std::string_view tag_token, const TextLine& line, std::size_t first_coordinate) {
    const std::int64_t tag = text_.parse_integer(tag_token, "node number");
    const double x = text_.parse_coordinate(line[first_coordinate], "node", tag);
    const double y = text_.parse_coordinate(line[first_coordinate + 1], "node", tag);
    const double z = text_.parse_coordinate(line[first_coordinate + 2], "node", tag);
    if (!node_index_.emplace(tag, mesh_.vertex_count()).second) {
      text_.fail(concat("node ", tag, " is defined twice"));
    }
    mesh_.add_vertex(x, y, z);
  }

  void read_nodes() {
    if (nodes_read_) {
      text_.fail(concat("second ", nodes_section(), " section (only one is supported)"));
    }
    nodes_read_ = true;
    if (version_ == MshVersion::kV4) {
      read_node_blocks();
      return;
    }
    const std::int64_t count = read_count(1, "number of nodes", "nodes", 0);
    node_index_.reserve(static_cast<std::size_t>(count));
    for (std::int64_t i = 0; i < count; ++i) {
      const TextLine line = item_line(i, count, "nodes", nodes_section());
      text_.require_tokens(line, 4, "node-number x y z");
      add_node(line[0], line, 1);
    }
    expect_section_end(nodes_section(), count, "nodes");
  }

  // MSH 4.1: "numEntityBlocks numNodes minNodeTag maxNodeTag", then per block
  // "entityDim entityTag parametric numNodesInBlock", the block's tags, then its coordinates
  // (followed by entityDim parametric coordinates when parametric is 1).
  void read_node_blocks() {
    const std::int64_t total =
        read_count(4, "numEntityBlocks numNodes minNodeTag maxNodeTag", "nodes", 1);
    node_index_.reserve(static_cast<std::size_t>(total));
    std::int64_t read = 0;
    std::vector<std::string_view> tags;
    while (read < total) {
      const TextLine block = item_line(read, total, "nodes", "$Nodes");
      text_.require_tokens(block, 4, "entityDim entityTag parametric numNodesInBlock");
      const int dimension = text_.parse_count(block[0], "entity dimension");
      const bool parametric = text_.parse_integer(block[2], "parametric flag") != 0;
      const int in_block = text_.parse_count(block[3], "number of nodes in the block");
      if (in_block > total - read) {
        text_.fail(concat("node block of ", in_block, " nodes exceeds the ", total,
                          " nodes the $Nodes header declares"));
      }
      tags.clear();
      while (static_cast<int>(tags.size()) < in_block) {
        const TextLine line = item_line(read, total, "nodes", "$Nodes");
        tags.insert(tags.end(), line.tokens.begin(), line.tokens.end());
      }
      if (static_cast<int>(tags.size()) != in_block) {
        text_.fail(concat("node block lists ", tags.size(), " tags, expected ", in_block));
      }
      const std::size_t values = 3 + (parametric ? static_cast<std::size_t>(dimension) : 0);
      for (const std::string_view tag : tags) {
        const TextLine line = item_line(read, total, "nodes", "$Nodes");
        text_.require_tokens(line, values,
                             parametric ? "x y z and parametric coordinates" : "x y z");
        add_node(tag, line, 0);
        ++read;
      }
    }
    expect_section_end("$Nodes", total, "nodes");
  }

  const ElementKind& element_kind(std::string_view type_token) const {
    const std::int64_t type = text_.parse_integer(type_token, "element type");
    const auto kind = std::find_if(kElementKinds.begin(), kElementKinds.end(),
                                   [type](const ElementKind& k) { return k.type == type; });
    if (kind == kElementKinds.end()) {
      text_.fail(
          concat("unsupported element type ", type, element_type_name(type),
                 "; expected 2 (triangle) or 4 (tetrahedron), or 1 (line) or 15 (point), which "
                 "are skipped"));
    }
    return *kind;
  }

  // Fails unless `line` holds `leading` values (`layout`), then the element's node numbers.
  void require_element_values(const TextLine& line,
                              std::size_t leading,
                              std::string_view layout,
                              const ElementKind& kind) const {
    const std::size_t expected = leading + static_cast<std::size_t>(kind.nodes);
    if (line.size() != expected) {  // the message is built only when needed: once per element
      text_.require_tokens(line, expected, concat(layout, " and ", kind.nodes, " node numbers"));
    }
  }

  void add_element(const ElementKind& kind,
                   std::string_view id,
                   const TextLine& line,
                   std::size_t first_node) {
    if (!kind.kept) {
      return;
    }
    std::array<int, 4> vertices{};
    for (int i = 0; i < kind.nodes; ++i) {
      const std::string_view tag_token = line[first_node + static_cast<std::size_t>(i)];
      const auto found = node_index_.find(text_.parse_integer(tag_token, "node number"));
      if (found == node_index_.end()) {
        text_.fail(concat("element ", id, " refers to node ", tag_token, ", which ",
                          nodes_section(), " does not define"));
      }
      vertices[static_cast<std::size_t>(i)] = found->second;
    }
    if (kind.nodes == 3) {
      mesh_.add_triangle(vertices[0], vertices[1], vertices[2]);
    } else {
      mesh_.add_tetrahedron(vertices[0], vertices[1], vertices[2], vertices[3]);
    }
  }

  void read_elements() {
    if (!nodes_read_) {
      text_.fail(concat(elements_section(), " before ", nodes_section(),
                        ": its node numbers cannot be resolved"));
    }
    if (version_ == MshVersion::kV4) {
      read_element_blocks();
      return;
    }
    const std::int64_t count = read_count(1, "number of elements", "elements", 0);
    for (std::int64_t i = 0; i < count; ++i) {
      const TextLine line = item_line(i, count, "elements", elements_section());
      if (version_ == MshVersion::kV1) {
        // elm-number elm-type reg-phys reg-elem number-of-nodes node-number-list
        text_.require_min_tokens(line, 5, "elm-number elm-type reg-phys reg-elem number-of-nodes");
        const ElementKind& kind = element_kind(line[1]);
        require_element_values(line, 5, "elm-number elm-type reg-phys reg-elem number-of-nodes",
                               kind);
        if (text_.parse_integer(line[4], "number of nodes") != kind.nodes) {
          text_.fail(concat("element type ", kind.type, " has ", kind.nodes,
                            " nodes, but the line says ", line[4]));
        }
        add_element(kind, line[0], line, 5);
      } else {
        // elm-number elm-type number-of-tags tags... node-number-list
        text_.require_min_tokens(line, 3, "elm-number elm-type number-of-tags");
        const ElementKind& kind = element_kind(line[1]);
        const std::size_t tags =
            static_cast<std::size_t>(text_.parse_count(line[2], "number of tags"));
        require_element_values(line, 3 + tags, "elm-number elm-type number-of-tags, the tags",
                               kind);
        add_element(kind, line[0], line, 3 + tags);
      }
    }
    expect_section_end(elements_section(), count, "elements");
  }

  // MSH 4.1: "numEntityBlocks numElements minElementTag maxElementTag", then per block
  // "entityDim entityTag elementType numElementsInBlock" and one "tag nodes..." line per element.
  void read_element_blocks() {
    const std::int64_t total =
        read_count(4, "numEntityBlocks numElements minElementTag maxElementTag", "elements", 1);
    std::int64_t read = 0;
    while (read < total) {
      const TextLine block = item_line(read, total, "elements", "$Elements");
      text_.require_tokens(block, 4, "entityDim entityTag elementType numElementsInBlock");
      const ElementKind& kind = element_kind(block[2]);
      const int in_block = text_.parse_count(block[3], "number of elements in the block");
      if (in_block > total - read) {
        text_.fail(concat("element block of ", in_block, " elements exceeds the ", total,
                          " elements the $Elements header declares"));
      }
      for (int i = 0; i < in_block; ++i, ++read) {
        const TextLine line = item_line(read, total, "elements", "$Elements");
        require_element_values(line, 1, "element tag", kind);
        add_element(kind, line[0], line, 1);
      }
    }
    expect_section_end("$Elements", total, "elements");
  }

  TextTokenizer text_;
  MshVersion version_ = MshVersion::kV2;
  MeshBuilder mesh_;
  std::unordered_map<std::int64_t, int> node_index_;  // file node tag -> 0-based vertex
  bool nodes_read_ = false;
};

}  // namespace

MeshData read_msh(const std::filesystem::path& path) {
  return MshReader(path).read();
}

}  // namespace softbench
