// SPDX-License-Identifier: MIT
#include "geometry/byte_order.h"
#include "geometry/mesh_io.h"
#include "geometry/text_format.h"
#include "geometry/text_tokenizer.h"
#include "geometry/weld_vertices.h"

#include <algorithm>
#include <bit>
#include <cmath>
#include <cstdint>
#include <limits>
#include <string>
#include <string_view>
#include <vector>

// STL is a triangle soup: every triangle carries its own three corners. The readers collect the
// corners (x y z, three per triangle) and weld_vertices() turns the soup into a mesh.
namespace softbench {
namespace {

constexpr std::size_t kBinaryHeaderBytes = 84;    // 80-byte comment + uint32 triangle count
constexpr std::size_t kBinaryTriangleBytes = 50;  // normal, 3 corners (float32 x 12), uint16

std::uint32_t binary_triangle_count(const std::string& bytes) {
  return load_number<std::uint32_t>(bytes.data() + 80, std::endian::little);
}

std::uint64_t binary_size_for(std::uint32_t triangles) {
  return kBinaryHeaderBytes + kBinaryTriangleBytes * std::uint64_t{triangles};
}

bool has_binary_size(const std::string& bytes) {
  return bytes.size() >= kBinaryHeaderBytes
         && binary_size_for(binary_triangle_count(bytes)) == bytes.size();
}

// Why a file that is not ASCII cannot be binary either.
std::string binary_size_problem(const std::string& bytes) {
  if (bytes.size() < kBinaryHeaderBytes) {
    return concat("truncated: a binary STL needs an 84-byte header, file has ", bytes.size(),
                  " bytes");
  }
  const std::uint32_t triangles = binary_triangle_count(bytes);
  const std::uint64_t expected = binary_size_for(triangles);
  return concat(expected > bytes.size() ? "truncated" : "size mismatch", ": header says ",
                triangles, " triangles (", expected, " bytes), file has ", bytes.size(), " bytes");
}

// An ASCII file starts with "solid" and holds only text. Binary files often start with "solid"
// too (their free-form header), which is why the size formula is tried first.
bool looks_like_ascii(std::string_view bytes) {
  const std::size_t start = bytes.find_first_not_of(" \t\r\n");
  if (start == std::string_view::npos || bytes.substr(start, 5) != "solid") {
    return false;
  }
  return std::none_of(bytes.begin(), bytes.end(), [](char c) {
    const auto byte = static_cast<unsigned char>(c);
    return (byte < 0x20 && byte != '\t' && byte != '\n' && byte != '\r' && byte != '\f'
            && byte != '\v')
           || byte == 0x7f;
  });
}

std::vector<double> read_binary_corners(const std::string& bytes, const std::string& file) {
  const std::uint32_t count = binary_triangle_count(bytes);
  std::vector<double> corners;
  corners.reserve(9 * std::size_t{count});  // has_binary_size() checked the count
  for (std::uint32_t t = 0; t < count; ++t) {
    // Normals are skipped: they are recomputed from the corners, and exporters write NaN ones
    // for degenerate triangles.
    const char* corner = bytes.data() + kBinaryHeaderBytes + kBinaryTriangleBytes * t + 12;
    for (int k = 0; k < 3; ++k) {
      for (int axis = 0; axis < 3; ++axis, corner += 4) {
        const double value = load_number<float>(corner, std::endian::little);
        if (!std::isfinite(value)) {
          throw_file_error(file, concat("triangle ", t + 1, ": vertex ", k + 1,
                                        " has a non-finite coordinate (", value, ")"));
        }
        corners.push_back(value);
      }
    }
  }
  return corners;
}

// The next line, which must be `statement` ("outer loop") or start with it ("vertex 1 2 3").
TextLine expect_statement(TextTokenizer& text, std::string_view statement) {
  std::optional<TextLine> line = text.next_line();
  const std::size_t space = statement.find(' ');
  const std::string_view first = statement.substr(0, space);
  const std::string_view second =
      space == std::string_view::npos ? std::string_view() : statement.substr(space + 1);
  if (!line || (*line)[0] != first
      || (!second.empty() && (line->size() < 2 || (*line)[1] != second))) {
    text.fail(concat("expected '", statement, "', found ",
                     line ? quoted_token((*line)[0]) : std::string("end of file")));
  }
  return std::move(*line);
}

// solid <name> / facet normal nx ny nz / outer loop / vertex x y z (x3) / endloop / endfacet /
// endsolid <name>; several solids may follow one another.
std::vector<double> read_ascii_corners(std::string bytes, const std::string& file) {
  TextTokenizer text(file, std::move(bytes));
  std::vector<double> corners;
  expect_statement(text, "solid");
  int facet = 0;
  // Binary floats cannot spread far enough to matter; ASCII doubles can (1e308 and -1e308).
  Eigen::Vector3d lowest = Eigen::Vector3d::Constant(std::numeric_limits<double>::infinity());
  Eigen::Vector3d highest = -lowest;
  while (true) {
    const TextLine line = text.expect_line("'facet normal' or 'endsolid'");
    if (line[0] == "endsolid") {
      const std::optional<TextLine> next_solid = text.next_line();
      if (!next_solid) {
        break;
      }
      if ((*next_solid)[0] != "solid") {
        text.fail(concat("expected 'solid' or the end of the file after 'endsolid', found ",
                         quoted_token((*next_solid)[0])));
      }
      continue;
    }
    if (line[0] != "facet") {
      text.fail(concat("expected 'facet normal' or 'endsolid', found ", quoted_token(line[0])));
    }
    ++facet;
    expect_statement(text, "outer loop");
    for (int k = 0; k < 3; ++k) {
      const TextLine vertex = expect_statement(text, "vertex");
      text.require_tokens(vertex, 4, "vertex x y z");
      Eigen::Vector3d corner;
      for (int axis = 0; axis < 3; ++axis) {
        corner(axis) = text.parse_coordinate(vertex[static_cast<std::size_t>(axis) + 1], "facet",
                                             facet);
        corners.push_back(corner(axis));
      }
      lowest = lowest.cwiseMin(corner);
      highest = highest.cwiseMax(corner);
      if (!std::isfinite((highest - lowest).squaredNorm())) {
        text.fail(concat("facet ", facet, " has a vertex too far from the others (",
                         format_vector(corner),
                         "): welding squares the vertices' bounding-box diagonal, which would "
                         "overflow a double"));
      }
    }
    expect_statement(text, "endloop");
    expect_statement(text, "endfacet");
  }
  return corners;
}

}  // namespace

MeshData read_stl(const std::filesystem::path& path, double weld_tolerance) {
  const std::string file = path.string();
  if (!(weld_tolerance >= 0.0)) {
    throw_file_error(file, concat("weld tolerance must be >= 0, got ", weld_tolerance));
  }
  std::string bytes = read_file_bytes(path);
  std::vector<double> corners;
  if (has_binary_size(bytes)) {
    corners = read_binary_corners(bytes, file);
  } else if (looks_like_ascii(bytes)) {
    corners = read_ascii_corners(std::move(bytes), file);
  } else {
    throw_file_error(file, binary_size_problem(bytes));
  }

  const Eigen::Index corner_count = static_cast<Eigen::Index>(corners.size() / 3);
  WeldedVertices welded = weld_vertices(
      Eigen::Map<const Eigen::Matrix3Xd>(corners.data(), 3, corner_count), weld_tolerance);

  MeshData mesh;
  mesh.vertices = std::move(welded.vertices);
  mesh.triangles = Eigen::Map<const Eigen::Matrix3Xi>(welded.index_of.data(), 3, corner_count / 3);
  mesh.source = file;
  return mesh;
}

}  // namespace softbench
