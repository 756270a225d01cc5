// SPDX-License-Identifier: MIT
#include "geometry/byte_order.h"
#include "geometry/mesh_io.h"
#include "geometry/text_tokenizer.h"
#include "geometry/weld_vertices.h"

#include <algorithm>
#include <bit>
#include <cmath>
#include <cstdint>
#include <sstream>
#include <string>
#include <string_view>
#include <vector>

// STL is a triangle soup: every triangle carries its own three corners. The readers collect the
// corners (x y z, three per triangle) and weld_vertices() turns the soup into a mesh.
namespace softbench {
namespace {

constexpr std::size_t kBinaryHeaderBytes = 84;    // 80-byte comment + uint32 triangle count
constexpr std::size_t kBinaryTriangleBytes = 50;  // normal, 3 corners (float32 x 12), uint16

std::uint64_t binary_size_for(const std::string& bytes) {
  const auto count = load_number<std::uint32_t>(bytes.data() + 80, std::endian::little);
  return kBinaryHeaderBytes + kBinaryTriangleBytes * std::uint64_t{count};
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
  const auto count = load_number<std::uint32_t>(bytes.data() + 80, std::endian::little);
  std::vector<double> corners;
  corners.reserve(9 * std::size_t{count});  // the caller checked the size against the count
  for (std::uint32_t t = 0; t < count; ++t) {
    // Normals are skipped: they are recomputed from the corners, and exporters write NaN ones
    // for degenerate triangles.
    const char* corner = bytes.data() + kBinaryHeaderBytes + kBinaryTriangleBytes * t + 12;
    for (int k = 0; k < 3; ++k) {
      for (int axis = 0; axis < 3; ++axis, corner += 4) {
        const double value = load_number<float>(corner, std::endian::little);
        if (!std::isfinite(value)) {
          std::ostringstream problem;
          problem << "triangle " << t + 1 << ": vertex " << k + 1
                  << " has a non-finite coordinate (" << value << ")";
          throw_file_error(file, problem.str());
        }
        corners.push_back(value);
      }
    }
  }
  return corners;
}

// solid <name> / facet normal nx ny nz / outer loop / vertex x y z (x3) / endloop / endfacet /
// endsolid <name>; several solids may follow one another.
std::vector<double> read_ascii_corners(std::string bytes, const std::string& file) {
  TextTokenizer text(file, std::move(bytes));
  const auto expect = [&text](std::string_view first, std::string_view second) {
    const std::string statement = second.empty() ? std::string(first) : concat(first, " ", second);
    TextLine line = text.expect_line(concat("'", statement, "'"));
    if (line[0] != first || (!second.empty() && (line.size() < 2 || line[1] != second))) {
      text.fail(concat("expected '", statement, "', found ", quoted_token(line[0])));
    }
    return line;
  };
  std::vector<double> corners;
  expect("solid", "");
  int facet = 0;
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
    expect("outer", "loop");
    for (int k = 1; k <= 3; ++k) {
      const TextLine vertex = expect("vertex", "");
      text.require_tokens(vertex, 4, "vertex x y z");
      const std::string owner = concat("vertex ", k, " of facet ", facet);
      for (std::size_t axis = 1; axis <= 3; ++axis) {
        corners.push_back(text.parse_coordinate(vertex[axis], owner));
      }
    }
    expect("endloop", "");
    expect("endfacet", "");
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
  if (bytes.size() >= kBinaryHeaderBytes && binary_size_for(bytes) == bytes.size()) {
    corners = read_binary_corners(bytes, file);
  } else if (looks_like_ascii(bytes)) {
    corners = read_ascii_corners(std::move(bytes), file);
  } else if (bytes.size() < kBinaryHeaderBytes) {
    throw_file_error(file, concat("truncated: a binary STL needs an 84-byte header, file has ",
                                  bytes.size(), " bytes"));
  } else {
    const auto count = load_number<std::uint32_t>(bytes.data() + 80, std::endian::little);
    std::ostringstream problem;
    problem << (binary_size_for(bytes) > bytes.size() ? "truncated" : "size mismatch")
            << ": header says " << count << " triangles (" << binary_size_for(bytes)
            << " bytes), file has " << bytes.size() << " bytes";
    throw_file_error(file, problem.str());
  }

  const Eigen::Index corner_count = static_cast<Eigen::Index>(corners.size() / 3);
  const Eigen::Map<const Eigen::Matrix3Xd> soup(corners.data(), 3, corner_count);
  const double diagonal =
      corner_count == 0 ? 0.0 : (soup.rowwise().maxCoeff() - soup.rowwise().minCoeff()).norm();
  WeldedVertices welded = weld_vertices(soup, weld_tolerance * diagonal);

  MeshData mesh;
  mesh.vertices = std::move(welded.vertices);
  mesh.triangles = Eigen::Map<const Eigen::Matrix3Xi>(welded.index_of.data(), 3, corner_count / 3);
  mesh.source = file;
  return mesh;
}

}  // namespace softbench
