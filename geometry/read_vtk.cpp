// SPDX-License-Identifier: MIT
#include "geometry/byte_order.h"
#include "geometry/mesh_builder.h"
#include "geometry/mesh_io.h"
#include "geometry/text_tokenizer.h"
#include "geometry/vtk_cells.h"

#include <algorithm>
#include <array>
#include <bit>
#include <cctype>
#include <cmath>
#include <cstdint>
#include <limits>
#include <string>
#include <string_view>
#include <vector>

// Legacy VTK: four header lines (version, title, ASCII|BINARY, DATASET), then keyword lines each
// followed by their data, as whitespace-separated text or as raw big-endian binary starting on
// the next line. Only the geometry is read; attribute data (POINT_DATA, CELL_DATA) ends it.
namespace softbench {
namespace {

struct VtkDataType {
  std::string_view name;
  std::size_t bytes = 0;
  enum class Kind { kReal, kSigned, kUnsigned } kind = Kind::kReal;
};

// Binary sizes as the legacy writer uses them; vtkIdType is written as a 32-bit int.
constexpr std::array<VtkDataType, 17> kDataTypes = {{
    {"float", 4, VtkDataType::Kind::kReal},
    {"double", 8, VtkDataType::Kind::kReal},
    {"char", 1, VtkDataType::Kind::kSigned},
    {"signed_char", 1, VtkDataType::Kind::kSigned},
    {"unsigned_char", 1, VtkDataType::Kind::kUnsigned},
    {"short", 2, VtkDataType::Kind::kSigned},
    {"unsigned_short", 2, VtkDataType::Kind::kUnsigned},
    {"int", 4, VtkDataType::Kind::kSigned},
    {"unsigned_int", 4, VtkDataType::Kind::kUnsigned},
    {"long", 8, VtkDataType::Kind::kSigned},
    {"unsigned_long", 8, VtkDataType::Kind::kUnsigned},
    {"vtkIdType", 4, VtkDataType::Kind::kSigned},
    {"vtktypeint32", 4, VtkDataType::Kind::kSigned},
    {"vtktypeuint32", 4, VtkDataType::Kind::kUnsigned},
    {"vtktypeint64", 8, VtkDataType::Kind::kSigned},
    {"vtktypeuint64", 8, VtkDataType::Kind::kUnsigned},
    {"bit", 0, VtkDataType::Kind::kUnsigned},  // listed to be named in the error below
}};
constexpr VtkDataType kLegacyCellInteger{"int", 4, VtkDataType::Kind::kSigned};

double decode_real(const char* bytes, const VtkDataType& type) {
  constexpr auto kBig = std::endian::big;
  switch (type.kind) {
    case VtkDataType::Kind::kReal:
      return type.bytes == 4 ? load_number<float>(bytes, kBig) : load_number<double>(bytes, kBig);
    case VtkDataType::Kind::kSigned:
      switch (type.bytes) {
        case 1:
          return load_number<std::int8_t>(bytes, kBig);
        case 2:
          return load_number<std::int16_t>(bytes, kBig);
        case 4:
          return load_number<std::int32_t>(bytes, kBig);
        default:
          return static_cast<double>(load_number<std::int64_t>(bytes, kBig));
      }
    case VtkDataType::Kind::kUnsigned:
      switch (type.bytes) {
        case 1:
          return load_number<std::uint8_t>(bytes, kBig);
        case 2:
          return load_number<std::uint16_t>(bytes, kBig);
        case 4:
          return load_number<std::uint32_t>(bytes, kBig);
        default:
          return static_cast<double>(load_number<std::uint64_t>(bytes, kBig));
      }
  }
  return 0.0;
}

std::int64_t decode_integer(const char* bytes, const VtkDataType& type) {
  constexpr auto kBig = std::endian::big;
  if (type.kind == VtkDataType::Kind::kSigned && type.bytes == 8) {
    return load_number<std::int64_t>(bytes, kBig);
  }
  if (type.kind == VtkDataType::Kind::kUnsigned && type.bytes == 8) {
    // Beyond int64 is out of any index range anyway; -1 gets reported as such.
    const std::uint64_t value = load_number<std::uint64_t>(bytes, kBig);
    return value > static_cast<std::uint64_t>(std::numeric_limits<std::int64_t>::max())
               ? -1
               : static_cast<std::int64_t>(value);
  }
  return static_cast<std::int64_t>(decode_real(bytes, type));
}

std::string upper(std::string_view word) {
  std::string result(word);
  std::transform(result.begin(), result.end(), result.begin(),
                 [](unsigned char c) { return static_cast<char>(std::toupper(c)); });
  return result;
}

class VtkReader {
 public:
  explicit VtkReader(const std::filesystem::path& path) : text_(path) {}

  MeshData read() {
    read_header();
    while (const std::optional<TextLine> line = text_.next_line()) {
      const std::string keyword = upper((*line)[0]);
      if (keyword == "POINT_DATA" || keyword == "CELL_DATA") {
        break;  // attributes only from here on
      }
      if (keyword == "POINTS") {
        read_points(*line);
      } else if (keyword == "FIELD") {
        skip_field(*line);
      } else if (keyword == "METADATA") {
        skip_metadata();
      } else if (polydata_
                 && (keyword == "POLYGONS" || keyword == "TRIANGLE_STRIPS" || keyword == "VERTICES"
                     || keyword == "LINES")) {
        read_polydata_cells(*line, keyword);
      } else if (!polydata_ && keyword == "CELLS") {
        read_grid_cells(*line);
      } else if (!polydata_ && keyword == "CELL_TYPES") {
        read_cell_types(*line);
      } else {
        text_.fail(concat("unexpected keyword ", quoted_token((*line)[0]), " in a ",
                          (polydata_ ? "POLYDATA" : "UNSTRUCTURED_GRID"), " dataset"));
      }
    }
    if (!have_points_) {
      text_.fail("no POINTS section in the file");
    }
    if (have_grid_cells_ && !have_cell_types_) {
      text_.fail_at(cells_line_, "CELLS without CELL_TYPES");
    }
    if (have_grid_cells_) {
      if (auto problem = append_cells_by_type(grid_cells_, cell_types_, mesh_)) {
        text_.fail_at(cell_types_line_, *problem);
      }
    }
    return mesh_.finish(text_.file());
  }

 private:
  void read_header() {
    const std::optional<std::string_view> version_line = text_.next_raw_line();
    constexpr std::string_view kMagic = "# vtk DataFile Version ";
    if (!version_line || version_line->size() <= kMagic.size()
        || upper(version_line->substr(0, kMagic.size())) != upper(kMagic)) {
      text_.fail(
          concat("expected '# vtk DataFile Version x.y' as the first line of a legacy VTK file, "
                 "found ",
                 quoted_token(version_line.value_or("end of file"))));
    }
    const std::string_view version = version_line->substr(kMagic.size());
    const int major = version.empty() ? 0 : version[0] - '0';
    const int minor = version.size() >= 3 && version[1] == '.' ? version[2] - '0' : 0;
    if (major < 2 || major > 5 || (major == 5 && minor > 1)) {
      text_.fail(
          concat("unsupported VTK file version ", quoted_token(version), " (expected 2.0 to 5.1)"));
    }
    offsets_layout_ = major >= 5;
    if (!text_.next_raw_line()) {
      text_.fail("expected a title line, found end of file");
    }
    const TextLine encoding = text_.expect_line("ASCII or BINARY");
    const std::string encoding_name = upper(encoding[0]);
    if (encoding_name != "ASCII" && encoding_name != "BINARY") {
      text_.fail(concat("expected ASCII or BINARY, found ", quoted_token(encoding[0])));
    }
    binary_ = encoding_name == "BINARY";
    const TextLine dataset = text_.expect_line("DATASET POLYDATA or DATASET UNSTRUCTURED_GRID");
    if (upper(dataset[0]) != "DATASET" || dataset.size() != 2) {
      text_.fail(concat("expected 'DATASET POLYDATA' or 'DATASET UNSTRUCTURED_GRID', found ",
                        quoted_token(dataset[0])));
    }
    const std::string kind = upper(dataset[1]);
    if (kind != "POLYDATA" && kind != "UNSTRUCTURED_GRID") {
      text_.fail(concat("unsupported dataset ", quoted_token(dataset[1]),
                        " (expected POLYDATA or UNSTRUCTURED_GRID)"));
    }
    polydata_ = kind == "POLYDATA";
  }

  const VtkDataType& data_type(std::string_view name) const {
    const auto found = std::find_if(kDataTypes.begin(), kDataTypes.end(),
                                    [name](const VtkDataType& type) { return type.name == name; });
    if (found == kDataTypes.end() || found->bytes == 0) {
      text_.fail(concat("unsupported data type ", quoted_token(name)));
    }
    return *found;
  }

  // `count` values of `type` as text tokens or big-endian binary. `what` names them in errors.
  template <typename Value, typename ParseText, typename Decode>
  std::vector<Value> read_values(std::int64_t count,
                                 const VtkDataType& type,
                                 const std::string& what,
                                 ParseText parse_text,
                                 Decode decode) {
    std::vector<Value> values;
    if (binary_) {
      const std::string_view bytes = text_.read_bytes(byte_count(count, type, what), what);
      values.reserve(static_cast<std::size_t>(count));
      for (std::size_t i = 0; i < bytes.size(); i += type.bytes) {
        values.push_back(decode(bytes.data() + i, values.size()));
      }
    } else {
      values.reserve(text_.check_count_fits(count, concat("values of ", what)));
      while (static_cast<std::int64_t>(values.size()) < count) {
        const std::optional<std::string_view> token = text_.next_token();
        if (!token) {
          text_.fail(concat("expected ", count, " values of ", what, ", found ", values.size(),
                            " before end of file"));
        }
        values.push_back(parse_text(*token, values.size()));
      }
    }
    return values;
  }

  std::vector<std::int64_t> read_integers(std::int64_t count,
                                          const VtkDataType& type,
                                          const std::string& what) {
    return read_values<std::int64_t>(
        count, type, what,
        [&](std::string_view token, std::size_t) { return text_.parse_integer(token, what); },
        [&](const char* bytes, std::size_t) {
          if (type.kind == VtkDataType::Kind::kReal) {
            // An index stored as a float must be a whole number: 0.7 is no vertex, and a NaN
            // cast to an integer is undefined.
            const double value = decode_real(bytes, type);
            if (!std::isfinite(value) || value != std::floor(value)
                || std::abs(value) > 9.007199254740992e15) {
              text_.fail(concat(what, ": value ", value, " is not a whole number"));
            }
            return static_cast<std::int64_t>(value);
          }
          return decode_integer(bytes, type);
        });
  }

  // count values of `type` in bytes, checked against what is left of the file before it is
  // multiplied: a count near 2^62 would wrap around to a small byte count and be accepted.
  std::size_t byte_count(std::int64_t count, const VtkDataType& type, const std::string& what) {
    const auto wanted = static_cast<std::uint64_t>(std::max<std::int64_t>(count, 0));
    if (wanted > std::numeric_limits<std::size_t>::max() / type.bytes) {
      text_.fail(concat("truncated: ", what, " needs ", count, " x ", type.bytes,
                        " bytes of binary data, only ", text_.bytes_left(), " remain"));
    }
    return static_cast<std::size_t>(wanted * type.bytes);
  }

  // POINTS n type
  void read_points(const TextLine& line) {
    if (have_points_) {
      text_.fail("second POINTS section");
    }
    text_.require_tokens(line, 3, "POINTS n type");
    const int count = text_.parse_count(line[1], "number of points");
    const VtkDataType& type = data_type(line[2]);
    std::vector<double> coordinates = read_values<double>(
        3 * std::int64_t{count}, type, "POINTS",
        [&](std::string_view token, std::size_t i) {
          return text_.parse_coordinate(token, "point", static_cast<std::int64_t>(i / 3));
        },
        [&](const char* bytes, std::size_t i) {
          const double value = decode_real(bytes, type);
          if (!std::isfinite(value)) {
            text_.fail(concat("point ", i / 3, " has a non-finite coordinate (", value, ")"));
          }
          return value;
        });
    mesh_.coordinates = std::move(coordinates);
    have_points_ = true;
  }

  void require_points(std::string_view keyword) const {
    if (!have_points_) {
      text_.fail(concat(keyword, " before POINTS: cell indices cannot be checked"));
    }
  }

  // Legacy: "KEYWORD n size" then `size` ints ("k i_1 ... i_k" per cell). Version 5.1:
  // "KEYWORD n_offsets n_connectivity", "OFFSETS type" and values, "CONNECTIVITY type" and values.
  VtkCellArray read_cell_array(const TextLine& header) {
    text_.require_tokens(header, 3, concat(header[0], " n size"));
    const int first = text_.parse_count(header[1], "number of cells");
    const int second = text_.parse_count(header[2], "size of the cell list");
    const std::string keyword(header[0]);
    VtkCellArray cells;
    if (!offsets_layout_) {
      const std::vector<std::int64_t> legacy = read_integers(second, kLegacyCellInteger, keyword);
      if (auto problem = cells_from_legacy(legacy, static_cast<std::size_t>(first), cells)) {
        text_.fail_at(header.number, concat(keyword, ": ", *problem));
      }
      return cells;
    }
    cells.offsets = read_named_integers("OFFSETS", first, keyword);
    cells.connectivity = read_named_integers("CONNECTIVITY", second, keyword);
    if (cells.offsets.empty()) {
      cells.offsets.push_back(0);  // zero cells may be written with no offsets at all
    }
    if (auto problem = check_offsets(cells)) {
      text_.fail_at(header.number, concat(keyword, ": ", *problem));
    }
    return cells;
  }

  std::vector<std::int64_t> read_named_integers(std::string_view name,
                                                int count,
                                                const std::string& keyword) {
    const TextLine line = text_.expect_line(concat(name, " type"));
    if (upper(line[0]) != name || line.size() != 2) {
      text_.fail(concat("expected '", name, " <type>' in the ", keyword,
                        " section of a version 5 file, found ", quoted_token(line[0])));
    }
    return read_integers(count, data_type(line[1]), concat(keyword, " ", name));
  }

  void read_polydata_cells(const TextLine& header, const std::string& keyword) {
    require_points(keyword);
    const VtkCellArray cells = read_cell_array(header);
    std::optional<std::string> problem;
    if (keyword == "POLYGONS") {
      problem = append_polygons(cells, mesh_);
    } else if (keyword == "TRIANGLE_STRIPS") {
      problem = append_triangle_strips(cells, mesh_);
    }  // VERTICES and LINES hold no surface
    if (problem) {
      text_.fail_at(header.number, concat(keyword, ": ", *problem));
    }
  }

  // Unstructured grid cells wait for CELL_TYPES to say which are triangles and tets.
  void read_grid_cells(const TextLine& header) {
    require_points("CELLS");
    if (have_grid_cells_) {
      text_.fail("second CELLS section");
    }
    cells_line_ = header.number;
    grid_cells_ = read_cell_array(header);
    have_grid_cells_ = true;
  }

  // CELL_TYPES n, then n ints
  void read_cell_types(const TextLine& line) {
    text_.require_tokens(line, 2, "CELL_TYPES n");
    if (!have_grid_cells_ || have_cell_types_) {
      text_.fail(have_cell_types_ ? "second CELL_TYPES section" : "CELL_TYPES before CELLS");
    }
    have_cell_types_ = true;
    cell_types_line_ = line.number;
    cell_types_ = read_integers(text_.parse_count(line[1], "number of cell types"),
                                kLegacyCellInteger, "CELL_TYPES");
  }

  // FIELD name n, then per array "name components tuples type" and components x tuples values.
  void skip_field(const TextLine& line) {
    text_.require_tokens(line, 3, "FIELD name number-of-arrays");
    const int arrays = text_.parse_count(line[2], "number of arrays");
    for (int a = 0; a < arrays; ++a) {
      TextLine array = text_.expect_line("field array 'name components tuples type'");
      if (upper(array[0]) == "METADATA") {  // version 5 may describe the previous array
        skip_metadata();
        array = text_.expect_line("field array 'name components tuples type'");
      }
      text_.require_tokens(array, 4, "field array 'name components tuples type'");
      const std::int64_t values = std::int64_t{text_.parse_count(array[1], "number of components")}
                                  * text_.parse_count(array[2], "number of tuples");
      const VtkDataType& type = data_type(array[3]);
      const std::string what = concat("values of field array ", quoted_token(array[0]));
      if (binary_) {
        text_.read_bytes(byte_count(values, type, what), what);
      } else {
        text_.check_count_fits(values, what);
        for (std::int64_t i = 0; i < values; ++i) {
          text_.expect_token(what);
        }
      }
    }
  }

  // METADATA blocks (version 5) run to the next blank line.
  void skip_metadata() {
    while (const std::optional<std::string_view> line = text_.next_raw_line()) {
      if (line->find_first_not_of(" \t\r") == std::string_view::npos) {
        return;
      }
    }
  }

  TextTokenizer text_;
  bool binary_ = false;
  bool polydata_ = true;
  bool offsets_layout_ = false;  // version 5.1: OFFSETS/CONNECTIVITY arrays
  MeshBuilder mesh_;
  bool have_points_ = false;
  bool have_grid_cells_ = false;
  bool have_cell_types_ = false;
  VtkCellArray grid_cells_;
  std::vector<std::int64_t> cell_types_;
  int cells_line_ = 0;
  int cell_types_line_ = 0;
};

}  // namespace

MeshData read_vtk(const std::filesystem::path& path) {
  return VtkReader(path).read();
}

}  // namespace softbench
