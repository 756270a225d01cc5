// SPDX-License-Identifier: MIT
#include "geometry/input_error.h"
#include "geometry/mesh_io.h"
#include "tests/geometry/mesh_file_test_support.h"
#include "tests/test_meshes.h"

#include <gmock/gmock.h>
#include <gtest/gtest.h>

#include <string>

namespace softbench {
namespace {

using test::random_bytes;
using test::TempDir;
using test::ThrowsInputError;

// Five points numbered from 1, with one attribute and a boundary marker, as `tetgen -p` writes.
constexpr const char* kNodeFromOne =
    "# bipyramid\n"
    "5 3 1 1\n"
    "1 0 0 0 7.5 1\n"
    "2 1 0 0 7.5 1\n"
    "3 0 1 0 7.5 1\n"
    "4 0 0 1 7.5 1\n"
    "5 0 0 -1 7.5 1  # below\n";

TEST(ReadTetgen, ReadsNodeEleAndFaceFilesFromTheBaseName) {
  TempDir dir;
  dir.write("mesh.1.node", kNodeFromOne);
  dir.write("mesh.1.ele", "2 4 1\n1 1 2 3 4 0\n2 1 3 2 5 0\n");
  dir.write("mesh.1.face", "# boundary\n2 1\n1 1 3 2 -1\n2 2 3 4 -1\n");
  const MeshData mesh = read_tetgen(dir.path() / "mesh.1");
  ASSERT_EQ(mesh.vertices.cols(), 5);
  ASSERT_EQ(mesh.tetrahedra.cols(), 2);
  ASSERT_EQ(mesh.triangles.cols(), 2);
  EXPECT_EQ(mesh.vertices.col(4), Eigen::Vector3d(0, 0, -1));
  EXPECT_EQ(mesh.tetrahedra.col(0), Eigen::Vector4i(0, 1, 2, 3));
  EXPECT_EQ(mesh.tetrahedra.col(1), Eigen::Vector4i(0, 2, 1, 4));
  EXPECT_EQ(mesh.triangles.col(1), Eigen::Vector3i(1, 2, 3));
}

TEST(ReadTetgen, ReadsZeroBasedFilesGivenAnyOfTheirExtensions) {
  TempDir dir;
  dir.write("tet.node", "4 3 0 0\n0 0 0 0\n1 1 0 0\n2 0 1 0\n3 0 0 1\n");
  dir.write("tet.ele", "1 4 0\n0 0 1 2 3\n");
  for (const char* name : {"tet.node", "tet.ele", "tet.ELE"}) {
    const MeshData mesh = read_tetgen(dir.path() / name);
    ASSERT_EQ(mesh.tetrahedra.cols(), 1) << name;
    EXPECT_EQ(mesh.tetrahedra.col(0), Eigen::Vector4i(0, 1, 2, 3)) << name;
    EXPECT_EQ(mesh.triangles.cols(), 0) << name;
  }
}

TEST(ReadTetgen, ReadsANodeFileAloneAsVerticesOnly) {
  TempDir dir;
  const MeshData mesh = read_tetgen(dir.write("points.node", kNodeFromOne));
  EXPECT_EQ(mesh.vertices.cols(), 5);
  EXPECT_EQ(mesh.tetrahedra.cols(), 0);
  EXPECT_EQ(mesh.triangles.cols(), 0);
}

TEST(ReadTetgen, RejectsSecondOrderTetrahedra) {
  TempDir dir;
  dir.write("quad.node", kNodeFromOne);
  dir.write("quad.ele", "1 10 0\n1 1 2 3 4 1 2 3 4 5 1\n");
  EXPECT_THAT([&] { read_tetgen(dir.path() / "quad"); },
              ThrowsInputError("quad.ele: line 1: second-order tetrahedra (10 nodes per tet) are "
                               "not supported; expected 4"));
}

TEST(ReadTetgen, RejectsVertexIndexOutOfRange) {
  TempDir dir;
  dir.write("range.node", kNodeFromOne);
  dir.write("range.ele", "2 4 0\n1 1 2 3 4\n2 1 3 2 6\n");
  EXPECT_THAT([&] { read_tetgen(dir.path() / "range"); },
              ThrowsInputError("range.ele: line 3: vertex index 6 out of range (range.node has 5 "
                               "points, numbered from 1)"));
}

TEST(ReadTetgen, RejectsFewerPointsThanTheHeaderSays) {
  TempDir dir;
  const std::string content = kNodeFromOne;
  const auto path = dir.write("cut.node", content.substr(0, content.find("5 0 0 -1")));
  EXPECT_THAT([&] { read_tetgen(path); },
              ThrowsInputError("cut.node: line 6: expected 5 points, found 4 before end of file"));
}

TEST(ReadTetgen, RejectsMoreFacesThanTheHeaderSays) {
  TempDir dir;
  dir.write("more.node", kNodeFromOne);
  dir.write("more.face", "1 0\n1 1 2 3\n2 2 3 4\n");
  EXPECT_THAT([&] { read_tetgen(dir.path() / "more"); },
              ThrowsInputError("more.face: line 3: expected 1 faces as the header says, found "
                               "more: '2'"));
}

TEST(ReadTetgen, RejectsIndicesThatAreNotConsecutive) {
  TempDir dir;
  const auto path = dir.write("gap.node", "3 3 0 0\n1 0 0 0\n2 1 0 0\n4 0 1 0\n");
  EXPECT_THAT([&] { read_tetgen(path); },
              ThrowsInputError("gap.node: line 4: expected point index 3, found 4 (indices must be "
                               "consecutive)"));
}

TEST(ReadTetgen, RejectsWrongNumberOfValuesOnAPointLine) {
  TempDir dir;
  const auto path = dir.write("short.node", "2 3 1 1\n1 0 0 0 7.5 1\n2 1 0 0 1\n");
  EXPECT_THAT([&] { read_tetgen(path); },
              ThrowsInputError("short.node: line 3: expected 6 values (index x y z, attributes, "
                               "marker), found 5"));
}

TEST(ReadTetgen, RejectsNanCoordinate) {
  TempDir dir;
  const auto path = dir.write("nan.node", "2 3 0 0\n0 0 0 0\n1 nan 0 0\n");
  EXPECT_THAT([&] { read_tetgen(path); },
              ThrowsInputError("nan.node: line 3: point 1 has a non-finite coordinate (nan)"));
}

TEST(ReadTetgen, RejectsTwoDimensionalPoints) {
  TempDir dir;
  const auto path = dir.write("flat.node", "1 2 0 0\n1 0 0\n");
  EXPECT_THAT([&] { read_tetgen(path); },
              ThrowsInputError("flat.node: line 1: dimension 2 is not supported; expected 3"));
}

TEST(ReadTetgen, RejectsAMissingNodeFile) {
  TempDir dir;
  dir.write("lonely.ele", "1 4 0\n1 1 2 3 4\n");
  EXPECT_THAT([&] { read_tetgen(dir.path() / "lonely.ele"); },
              ThrowsInputError("lonely.node: cannot open (No such file or directory)"));
}

TEST(ReadTetgen, RejectsRandomBytes) {
  TempDir dir;
  const auto path = dir.write("noise.node", random_bytes(5, 4096));
  EXPECT_THAT([&] { read_tetgen(path); }, ThrowsInputError("noise.node: line 1: expected at most 4 "
                                                           "values (#points dimension #attributes "
                                                           "#boundary-markers), found 7"));
}

TEST(ReadTetgen, RejectsAHugePointCountBeforeAllocating) {
  TempDir dir;
  const auto path = dir.write("huge.node", "2000000000 3 0 0\n1 0 0 0\n");
  EXPECT_THAT(
      [&] { read_tetgen(path); },
      ThrowsInputError("huge.node: line 1: truncated file or wrong count: 2000000000 points cannot "
                       "fit in the 8 bytes left in the file"));
}

}  // namespace
}  // namespace softbench
