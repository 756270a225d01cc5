// SPDX-License-Identifier: MIT
#include "geometry/input_error.h"
#include "geometry/mesh_io.h"
#include "tests/geometry/mesh_file_test_support.h"
#include "tests/test_meshes.h"
#include "tests/test_tolerances.h"

#include <gmock/gmock.h>
#include <gtest/gtest.h>

#include <cmath>
#include <cstdint>
#include <limits>
#include <sstream>
#include <string>

namespace softbench {
namespace {

using test::ByteWriter;
using test::cube_surface;
using test::random_bytes;
using test::TempDir;
using test::ThrowsInputError;

// A binary STL of `mesh`'s triangles: every triangle repeats its corners, as STL does. The header
// starts with "solid", as many exporters' headers do, to show the size formula decides.
std::string binary_stl(const MeshData& mesh) {
  ByteWriter out(std::endian::little);
  out.text("solid binary cube" + std::string(80 - 17, ' '));
  out.put(static_cast<std::uint32_t>(mesh.triangles.cols()));
  for (Eigen::Index t = 0; t < mesh.triangles.cols(); ++t) {
    out.put(0.0f).put(0.0f).put(0.0f);  // normal, ignored by readers
    for (Eigen::Index k = 0; k < 3; ++k) {
      for (Eigen::Index axis = 0; axis < 3; ++axis) {
        out.put(static_cast<float>(mesh.vertices(axis, mesh.triangles(k, t))));
      }
    }
    out.put(std::uint16_t{0});
  }
  return out.bytes();
}

std::string ascii_stl(const MeshData& mesh) {
  std::ostringstream out;
  out.precision(9);
  out << "solid cube\n";
  for (Eigen::Index t = 0; t < mesh.triangles.cols(); ++t) {
    out << "  facet normal 0 0 0\n    outer loop\n";
    for (Eigen::Index k = 0; k < 3; ++k) {
      const Eigen::Vector3d corner = mesh.vertices.col(mesh.triangles(k, t));
      out << "      vertex " << corner.x() << ' ' << corner.y() << ' ' << corner.z() << '\n';
    }
    out << "    endloop\n  endfacet\n";
  }
  out << "endsolid cube\n";
  return out.str();
}

// The welded mesh has the same triangles as `expected` up to a renumbering of its vertices.
void expect_same_surface(const MeshData& welded, const MeshData& expected) {
  ASSERT_EQ(welded.vertices.cols(), expected.vertices.cols());
  ASSERT_EQ(welded.triangles.cols(), expected.triangles.cols());
  for (Eigen::Index t = 0; t < expected.triangles.cols(); ++t) {
    for (Eigen::Index k = 0; k < 3; ++k) {
      EXPECT_TRUE(welded.vertices.col(welded.triangles(k, t))
                      .isApprox(expected.vertices.col(expected.triangles(k, t)), test::kFloat32))
          << "triangle " << t << " corner " << k;
    }
  }
}

TEST(ReadStl, ReadsAsciiAndWeldsSharedCorners) {
  TempDir dir;
  const MeshData cube = cube_surface();
  const MeshData mesh = read_stl(dir.write("cube.stl", ascii_stl(cube)));
  expect_same_surface(mesh, cube);
}

TEST(ReadStl, ReadsBinaryWhoseHeaderStartsWithSolid) {
  TempDir dir;
  const MeshData cube = cube_surface();
  const MeshData mesh = read_stl(dir.write("cube.stl", binary_stl(cube)));
  expect_same_surface(mesh, cube);
}

TEST(ReadStl, BinaryAndAsciiGiveTheSameWeldedMesh) {
  TempDir dir;
  MeshData surface = cube_surface();
  surface.vertices *= 0.3;  // not exact in float32: both paths must round the same way
  const MeshData from_binary = read_stl(dir.write("b.stl", binary_stl(surface)));
  const MeshData from_ascii = read_stl(dir.write("a.stl", ascii_stl(surface)));
  EXPECT_EQ(from_binary.triangles, from_ascii.triangles);
  ASSERT_EQ(from_binary.vertices.cols(), from_ascii.vertices.cols());
  EXPECT_TRUE(from_binary.vertices.isApprox(from_ascii.vertices, test::kFloat32));
}

TEST(ReadStl, WeldsCornersCloserThanTheToleranceOnly) {
  TempDir dir;
  // Two triangles sharing an edge whose copies differ by 1e-12 (merged at the default 1e-9 of the
  // diagonal) and a third corner 1e-3 away from the first (kept apart).
  const auto path = dir.write("near.stl",
                              "solid near\n"
                              "facet normal 0 0 1\nouter loop\n"
                              "vertex 0 0 0\nvertex 1 0 0\nvertex 0 1 0\n"
                              "endloop\nendfacet\n"
                              "facet normal 0 0 1\nouter loop\n"
                              "vertex 1.000000000001 0 0\nvertex 1 1 0\nvertex 0 1.000000000001 0\n"
                              "endloop\nendfacet\n"
                              "facet normal 0 0 1\nouter loop\n"
                              "vertex 0.001 0 0\nvertex 1 1 0\nvertex 0 1 0\n"
                              "endloop\nendfacet\n"
                              "endsolid near\n");
  const MeshData mesh = read_stl(path);
  EXPECT_EQ(mesh.vertices.cols(), 5);
  EXPECT_EQ(mesh.triangles.col(1), Eigen::Vector3i(1, 3, 2));
  EXPECT_EQ(read_stl(path, 0.01).vertices.cols(), 4);
}

TEST(ReadStl, WeldsALargeGridWithoutQuadraticCost) {
  TempDir dir;
  // 200 x 200 squares: 80000 triangles, 240000 corners, 40401 distinct points.
  constexpr int kSquares = 200;
  MeshData grid;
  grid.vertices.resize(3, (kSquares + 1) * (kSquares + 1));
  for (int j = 0; j <= kSquares; ++j) {
    for (int i = 0; i <= kSquares; ++i) {
      grid.vertices.col(j * (kSquares + 1) + i) << i * 0.01, j * 0.01, 0.0;
    }
  }
  grid.triangles.resize(3, 2 * kSquares * kSquares);
  for (int j = 0, t = 0; j < kSquares; ++j) {
    for (int i = 0; i < kSquares; ++i) {
      const int corner = j * (kSquares + 1) + i;
      grid.triangles.col(t++) << corner, corner + 1, corner + kSquares + 2;
      grid.triangles.col(t++) << corner, corner + kSquares + 2, corner + kSquares + 1;
    }
  }
  const MeshData mesh = read_stl(dir.write("grid.stl", binary_stl(grid)));
  EXPECT_EQ(mesh.vertices.cols(), grid.vertices.cols());
  EXPECT_EQ(mesh.triangles.cols(), grid.triangles.cols());
}

TEST(ReadStl, RejectsTruncatedBinary) {
  TempDir dir;
  const std::string bytes = binary_stl(cube_surface()).substr(0, 500);
  const auto path = dir.write("x.stl", bytes);
  EXPECT_THAT([&] { read_stl(path); },
              ThrowsInputError("x.stl: truncated: header says 12 triangles (684 bytes), file has "
                               "500 bytes"));
}

TEST(ReadStl, RejectsSolidFollowedByRandomBytes) {
  TempDir dir;
  const auto path = dir.write("fake.stl", "solid " + random_bytes(13, 1000));
  EXPECT_THAT([&] { read_stl(path); }, ThrowsInputError("fake.stl: truncated: header says "
                                                        "3602259007 triangles (180112950434 "
                                                        "bytes), file has 1006 bytes"));
  EXPECT_THAT([&] { read_stl(path); }, ThrowsInputError("fake.stl: truncated: header says "
                                                        "3602259007 triangles (180112950434 "
                                                        "bytes), file has 1006 bytes"));
}

TEST(ReadStl, RejectsAsciiTruncatedInsideAFacet) {
  TempDir dir;
  const std::string text = ascii_stl(cube_surface());
  const auto path = dir.write("cut.stl", text.substr(0, text.find("endloop")));
  EXPECT_THAT([&] { read_stl(path); },
              ThrowsInputError("cut.stl: line 6: expected 'endloop', found end of file"));
}

TEST(ReadStl, RejectsAsciiWithAMisspelledKeyword) {
  TempDir dir;
  const auto path =
      dir.write("typo.stl",
                "solid t\nfacet normal 0 0 1\nouter loop\nvertex 0 0 0\nvertex 1 0 0\n"
                "vertx 0 1 0\nendloop\nendfacet\nendsolid t\n");
  EXPECT_THAT([&] { read_stl(path); },
              ThrowsInputError("typo.stl: line 6: expected 'vertex', found 'vertx'"));
}

TEST(ReadStl, RejectsNanInBinary) {
  TempDir dir;
  MeshData cube = cube_surface();
  cube.vertices(1, cube.triangles(2, 1)) = std::numeric_limits<double>::quiet_NaN();
  const auto path = dir.write("nan.stl", binary_stl(cube));
  EXPECT_THAT([&] { read_stl(path); },
              ThrowsInputError("nan.stl: triangle 2: vertex 3 has a non-finite coordinate (nan)"));
}

TEST(ReadStl, RejectsNanInAscii) {
  TempDir dir;
  const auto path = dir.write("nan.stl",
                              "solid t\nfacet normal 0 0 1\nouter loop\nvertex 0 0 0\n"
                              "vertex 1 0 nan\nvertex 0 1 0\nendloop\nendfacet\nendsolid t\n");
  EXPECT_THAT([&] { read_stl(path); },
              ThrowsInputError("nan.stl: line 5: facet 1 has a non-finite coordinate (nan)"));
}

// Found while fuzzing read_stl: the welding's bounding-box diagonal overflowed to infinity and
// a cell coordinate became NaN, cast to an integer (undefined behaviour).
TEST(ReadStl, RejectsAsciiVerticesSpreadBeyondADouble) {
  TempDir dir;
  const auto path = dir.write("far.stl",
                              "solid t\nfacet normal 0 0 1\nouter loop\nvertex -1e308 0 0\n"
                              "vertex 1e308 0 0\nvertex 0 1 0\nendloop\nendfacet\nendsolid t\n");
  EXPECT_THAT([&] { read_stl(path); },
              ThrowsInputError("far.stl: line 5: facet 1 has a vertex too far from the others "
                               "([1e+308, 0, 0]): welding squares the vertices' bounding-box "
                               "diagonal, which would overflow a double"));
}

TEST(ReadStl, RejectsAFileShorterThanTheBinaryHeader) {
  TempDir dir;
  const auto path = dir.write("tiny.stl", random_bytes(17, 20));
  EXPECT_THAT(
      [&] { read_stl(path); },
      ThrowsInputError("tiny.stl: truncated: a binary STL needs an 84-byte header, file has "
                       "20 bytes"));
}

TEST(ReadStl, RejectsANegativeWeldTolerance) {
  TempDir dir;
  const auto path = dir.write("cube.stl", ascii_stl(cube_surface()));
  EXPECT_THAT([&] { read_stl(path, -1.0); }, ThrowsInputError("cube.stl: weld tolerance must be >= "
                                                              "0, got -1"));
}

}  // namespace
}  // namespace softbench
