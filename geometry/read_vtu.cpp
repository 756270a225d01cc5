// SPDX-License-Identifier: MIT
#include "geometry/mesh_builder.h"
#include "geometry/mesh_io.h"
#include "geometry/text_tokenizer.h"
#include "geometry/vtk_cells.h"

#include <algorithm>
#include <optional>
#include <string>
#include <string_view>
#include <vector>

// VTK XML UnstructuredGrid with ASCII DataArrays, as write_vtu() writes it. The XML is scanned
// tag by tag (no general XML parser): VTKFile > UnstructuredGrid > Piece > Points / Cells hold
// everything needed, other arrays are skipped.
namespace softbench {
namespace {

struct XmlTag {
  std::string_view name;
  std::string_view attributes;  ///< the text after the name
  bool closing = false;         ///< </Name>
  bool empty = false;           ///< <Name ... />
  int line = 0;
};

// The value of attribute `name` in `attributes` (name="value" or name='value').
std::optional<std::string_view> attribute(const XmlTag& tag, std::string_view name) {
  std::string_view rest = tag.attributes;
  while (true) {
    const std::size_t start = rest.find_first_not_of(" \t\r\n");
    if (start == std::string_view::npos) {
      return std::nullopt;
    }
    rest.remove_prefix(start);
    const std::size_t equals = rest.find('=');
    if (equals == std::string_view::npos || equals + 1 >= rest.size()) {
      return std::nullopt;
    }
    const std::string_view key = rest.substr(0, rest.substr(0, equals).find_last_not_of(" \t") + 1);
    const std::size_t open = rest.find_first_of("\"'", equals);
    const std::size_t close =
        open == std::string_view::npos ? open : rest.find(rest[open], open + 1);
    if (close == std::string_view::npos) {
      return std::nullopt;
    }
    if (key == name) {
      return rest.substr(open + 1, close - open - 1);
    }
    rest.remove_prefix(close + 1);
  }
}

class VtuReader {
 public:
  explicit VtuReader(const std::filesystem::path& path) : text_(path) {}

  MeshData read() {
    const std::optional<XmlTag> root = next_tag();
    if (!root || root->name != "VTKFile") {
      text_.fail(concat("not a VTK XML file: expected <VTKFile>, found ",
                        (root ? quoted_token(root->name) : std::string("no XML element"))));
    }
    if (attribute(*root, "type") != "UnstructuredGrid") {
      text_.fail(concat("expected a VTKFile of type UnstructuredGrid, found type ",
                        quoted_token(attribute(*root, "type").value_or(""))));
    }
    std::string_view section;  // the Points/Cells/PointData/... element we are inside
    while (const std::optional<XmlTag> tag = next_tag()) {
      if (tag->name == "Piece" && !tag->closing) {
        read_piece_sizes(*tag);
      } else if (tag->name == "AppendedData") {
        text_.fail("appended (binary) data is not supported; save the .vtu with ASCII data");
      } else if (tag->name == "DataArray" && !tag->closing) {
        read_data_array(*tag, section);
      } else if (tag->closing && tag->name == section) {
        section = {};
      } else if (!tag->closing && !tag->empty) {
        section = tag->name;
      }
    }
    return finish();
  }

 private:
  // The next element tag, skipping the <?xml ?> declaration, comments and text between tags.
  std::optional<XmlTag> next_tag() {
    while (text_.read_until("<")) {
      const std::optional<std::string_view> body = text_.read_until(">");
      if (!body) {
        text_.fail("unterminated XML tag");
      }
      if (body->starts_with("!--") && !body->ends_with("--")) {
        if (!text_.read_until("-->")) {
          text_.fail("unterminated XML comment");
        }
        continue;
      }
      if (body->empty() || body->front() == '?' || body->front() == '!') {
        continue;
      }
      XmlTag tag;
      tag.line = text_.line_number();
      std::string_view rest = *body;
      tag.closing = rest.front() == '/';
      if (tag.closing) {
        rest.remove_prefix(1);
      }
      tag.empty = !rest.empty() && rest.back() == '/';
      if (tag.empty) {
        rest.remove_suffix(1);
      }
      const std::size_t name_end = std::min(rest.find_first_of(" \t\r\n"), rest.size());
      tag.name = rest.substr(0, name_end);
      tag.attributes = rest.substr(name_end);
      return tag;
    }
    return std::nullopt;
  }

  int count_attribute(const XmlTag& tag, std::string_view name) const {
    const std::optional<std::string_view> value = attribute(tag, name);
    if (!value) {
      text_.fail_at(tag.line, concat("<", tag.name, "> has no ", name));
    }
    return text_.parse_count(*value, name);
  }

  void read_piece_sizes(const XmlTag& piece) {
    if (have_piece_) {
      text_.fail_at(piece.line, "more than one <Piece> (not supported)");
    }
    have_piece_ = true;
    point_count_ = count_attribute(piece, "NumberOfPoints");
    cell_count_ = count_attribute(piece, "NumberOfCells");
  }

  void read_data_array(const XmlTag& tag, std::string_view section) {
    const std::string name(attribute(tag, "Name").value_or(""));
    const std::string_view format = attribute(tag, "format").value_or("ascii");
    if (format != "ascii") {
      text_.fail_at(tag.line,
                    concat("DataArray ", quoted_token(name), " has format=", quoted_token(format),
                           "; only ascii arrays are supported (save the .vtu with ASCII data)"));
    }
    std::string_view content;
    int content_line = tag.line;
    if (!tag.empty) {
      const std::optional<std::string_view> text = text_.read_until("<");
      content_line = text_.line_number();
      const std::optional<std::string_view> end = text_.read_until(">");
      if (!text || !end || *end != "/DataArray") {
        text_.fail_at(tag.line, concat("DataArray ", quoted_token(name),
                                       " is not closed by "
                                       "</DataArray>"));
      }
      content = *text;
    }
    if (section == "Points") {
      read_points(tag, content, content_line);
    } else if (section == "Cells"
               && (name == "connectivity" || name == "offsets" || name == "types")) {
      std::vector<std::int64_t>& target = name == "connectivity" ? cells_.connectivity
                                          : name == "offsets"    ? offsets_
                                                                 : types_;
      TextTokenizer values(text_.file(), std::string(content), 0, content_line);
      while (const std::optional<std::string_view> token = values.next_token()) {
        target.push_back(values.parse_integer(*token, name));
      }
      if (name != "connectivity") {
        expect_count(tag, name, target.size(), std::size_t(cell_count_));
      }
    }  // other arrays (vertex fields) are not part of the mesh
  }

  void read_points(const XmlTag& tag, std::string_view content, int content_line) {
    if (attribute(tag, "NumberOfComponents") != "3") {
      text_.fail_at(tag.line, "the Points DataArray must have NumberOfComponents=\"3\"");
    }
    TextTokenizer values(text_.file(), std::string(content), 0, content_line);
    while (const std::optional<std::string_view> token = values.next_token()) {
      mesh_.coordinates.push_back(values.parse_coordinate(
          *token, "point", static_cast<std::int64_t>(mesh_.coordinates.size() / 3)));
    }
    have_points_ = true;
    expect_count(tag, "Points", mesh_.coordinates.size(), 3 * std::size_t(point_count_));
  }

  void expect_count(const XmlTag& tag,
                    std::string_view array,
                    std::size_t found,
                    std::size_t expected) const {
    if (found != expected) {
      text_.fail_at(tag.line, concat("DataArray ", quoted_token(array), " holds ", found,
                                     " values, expected ", expected,
                                     " from the Piece's NumberOfPoints/NumberOfCells"));
    }
  }

  MeshData finish() {
    if (!have_piece_) {
      text_.fail("no <Piece> in the file");
    }
    if (!have_points_ && point_count_ > 0) {
      text_.fail("no <Points> DataArray in the file");
    }
    if (offsets_.size() != std::size_t(cell_count_) || types_.size() != std::size_t(cell_count_)) {
      text_.fail(
          concat("<Cells> must hold connectivity, offsets and types for ", cell_count_, " cells"));
    }
    // .vtu offsets give where each cell ends; VtkCellArray also wants where the first begins.
    cells_.offsets.assign(1, 0);
    cells_.offsets.insert(cells_.offsets.end(), offsets_.begin(), offsets_.end());
    std::optional<std::string> problem = check_offsets(cells_);
    if (!problem) {
      problem = append_cells_by_type(cells_, types_, mesh_);
    }
    if (problem) {
      text_.fail(concat("<Cells>: ", *problem));
    }
    return mesh_.finish(text_.file());
  }

  TextTokenizer text_;
  MeshBuilder mesh_;
  bool have_piece_ = false;
  bool have_points_ = false;
  int point_count_ = 0;
  int cell_count_ = 0;
  VtkCellArray cells_;
  std::vector<std::int64_t> offsets_;
  std::vector<std::int64_t> types_;
};

}  // namespace

MeshData read_vtu(const std::filesystem::path& path) {
  return VtuReader(path).read();
}

}  // namespace softbench
