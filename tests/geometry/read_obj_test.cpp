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

TEST(ReadObj, ReadsVerticesAndTriangles) {
  TempDir dir;
  const auto path = dir.write("tet.obj",
                              "# a tet's surface\n"
                              "v 0 0 0\n"
                              "v 1.5 0 0\n"
                              "v 0 2.5 0\n"
                              "v 0 0 -3e-2\n"
                              "f 1 3 2\n"
                              "f 1 2 4\n"
                              "f 1 4 3\n"
                              "f 2 3 4\n");
  const MeshData mesh = read_obj(path);
  ASSERT_EQ(mesh.vertices.cols(), 4);
  ASSERT_EQ(mesh.triangles.cols(), 4);
  EXPECT_EQ(mesh.tetrahedra.cols(), 0);
  EXPECT_EQ(mesh.vertices.col(1), Eigen::Vector3d(1.5, 0, 0));
  EXPECT_EQ(mesh.vertices.col(3), Eigen::Vector3d(0, 0, -0.03));
  EXPECT_EQ(mesh.triangles.col(0), Eigen::Vector3i(0, 2, 1));
  EXPECT_EQ(mesh.triangles.col(3), Eigen::Vector3i(1, 2, 3));
  EXPECT_EQ(mesh.source, path.string());
}

TEST(ReadObj, FanTriangulatesPolygons) {
  TempDir dir;
  const auto path = dir.write("poly.obj",
                              "v 0 0 0\nv 1 0 0\nv 2 1 0\nv 1 2 0\nv 0 1 0\n"
                              "f 1 2 3 4\n"
                              "f 1 2 3 4 5\n");
  const MeshData mesh = read_obj(path);
  ASSERT_EQ(mesh.triangles.cols(), 2 + 3);
  EXPECT_EQ(mesh.triangles.col(0), Eigen::Vector3i(0, 1, 2));
  EXPECT_EQ(mesh.triangles.col(1), Eigen::Vector3i(0, 2, 3));
  EXPECT_EQ(mesh.triangles.col(4), Eigen::Vector3i(0, 3, 4));
}

TEST(ReadObj, AcceptsSlashFormsAndIgnoresTexturesNormalsAndGroups) {
  TempDir dir;
  // CRLF line ends, as in SOFA's liver.obj and stylus.obj.
  const auto path = dir.write("slashes.obj",
                              "mtllib liver.mtl\r\n"
                              "o liver\r\n"
                              "g default\r\n"
                              "v 0 0 0\r\nv 1 0 0\r\nv 0 1 0\r\nv 0 0 1\r\n"
                              "vt 0.5 0.5\r\n"
                              "vn 0 0 1\r\n"
                              "vp 0.2\r\n"
                              "usemtl red\r\n"
                              "s off\r\n"
                              "f 1/1/1 2/1/1 3/1/1\r\n"
                              "f 1//1 3//1 4//1   # trailing comment\r\n"
                              "f 2/1 4/1 3/1\r\n"
                              "l 1 2\r\n");
  const MeshData mesh = read_obj(path);
  EXPECT_EQ(mesh.vertices.cols(), 4);
  ASSERT_EQ(mesh.triangles.cols(), 3);
  EXPECT_EQ(mesh.triangles.col(1), Eigen::Vector3i(0, 2, 3));
  EXPECT_EQ(mesh.triangles.col(2), Eigen::Vector3i(1, 3, 2));
}

TEST(ReadObj, ResolvesNegativeIndicesAgainstTheVerticesSoFar) {
  TempDir dir;
  const auto path = dir.write("relative.obj",
                              "v 0 0 0\nv 1 0 0\nv 0 1 0\n"
                              "f -3 -2 -1\n"
                              "v 0 0 1\n"
                              "f -4/1 -1 -2\n");
  const MeshData mesh = read_obj(path);
  ASSERT_EQ(mesh.triangles.cols(), 2);
  EXPECT_EQ(mesh.triangles.col(0), Eigen::Vector3i(0, 1, 2));
  EXPECT_EQ(mesh.triangles.col(1), Eigen::Vector3i(0, 3, 2));
}

TEST(ReadObj, ReadsAPolylineAsVerticesWithoutTriangles) {
  TempDir dir;
  const auto path =
      dir.write("centerline.obj", "v 0 0 -3.5\nv 0 0 -3.25\nv 0 0 -3\nl 1 2\nl 2 3\n");
  const MeshData mesh = read_obj(path);
  EXPECT_EQ(mesh.vertices.cols(), 3);
  EXPECT_EQ(mesh.triangles.cols(), 0);
}

TEST(ReadObj, RejectsFaceIndexBeyondTheVertexCount) {
  TempDir dir;
  std::string content;
  for (int i = 0; i < 8; ++i) {
    content += "v " + std::to_string(i) + " 0 0\n";
  }
  content += "f 1 2 3\nf 1 2 4\nf 1 2 5\nf 3 40 1\n";  // line 12
  const auto path = dir.write("x.obj", content);
  EXPECT_THAT([&] { read_obj(path); },
              ThrowsInputError("x.obj: line 12: face index 40 out of range (file has 8 vertices)"));
}

TEST(ReadObj, RejectsFaceIndexZero) {
  TempDir dir;
  const auto path = dir.write("zero.obj", "v 0 0 0\nv 1 0 0\nv 0 1 0\nf 0 1 2\n");
  EXPECT_THAT(
      [&] { read_obj(path); },
      ThrowsInputError("zero.obj: line 4: face index 0 is invalid (OBJ indices start at 1)"));
}

TEST(ReadObj, RejectsRelativeIndexBeforeTheFirstVertex) {
  TempDir dir;
  const auto path = dir.write("neg.obj", "v 0 0 0\nv 1 0 0\nv 0 1 0\nf -1 -2 -4\n");
  EXPECT_THAT([&] { read_obj(path); },
              ThrowsInputError("neg.obj: line 4: relative face index -4 reaches before the first "
                               "vertex (3 vertices so far)"));
}

// Found by fuzz_obj: the smallest int64 was negated to compare it (undefined behaviour).
TEST(ReadObj, RejectsTheSmallestRelativeIndex) {
  TempDir dir;
  const auto path = dir.write("min.obj", "v 0 0 0\nf 1 1 -9223372036854775808\n");
  EXPECT_THAT([&] { read_obj(path); },
              ThrowsInputError("min.obj: line 2: relative face index -9223372036854775808 reaches "
                               "before the first vertex (1 vertices so far)"));
}

TEST(ReadObj, RejectsNanCoordinate) {
  TempDir dir;
  const auto path = dir.write("x.obj", "# comment\nv 0 0 0\nv 1 nan 0\n");
  EXPECT_THAT([&] { read_obj(path); },
              ThrowsInputError("x.obj: line 3: vertex 2 has a non-finite coordinate (nan)"));
}

TEST(ReadObj, RejectsInfiniteAndOverflowingCoordinates) {
  TempDir dir;
  const auto inf = dir.write("inf.obj", "v 0 -inf 0\n");
  const auto huge = dir.write("huge.obj", "v 0 0 1e999\n");
  EXPECT_THAT([&] { read_obj(inf); },
              ThrowsInputError("inf.obj: line 1: vertex 1 has a non-finite coordinate (-inf)"));
  EXPECT_THAT([&] { read_obj(huge); },
              ThrowsInputError("huge.obj: line 1: vertex 1 has a non-finite coordinate (1e999)"));
}

TEST(ReadObj, RejectsCoordinateThatIsNotANumber) {
  TempDir dir;
  const auto path = dir.write("bad.obj", "v 0 0 0\nv 1.2.3 0 0\n");
  EXPECT_THAT([&] { read_obj(path); },
              ThrowsInputError("bad.obj: line 2: vertex 2 has a coordinate that is not a number "
                               "('1.2.3')"));
}

TEST(ReadObj, RejectsTruncatedVertexLine) {
  TempDir dir;
  const auto path = dir.write("cut.obj", "v 0 0 0\nv 1 0 0\nv 0 1");
  EXPECT_THAT([&] { read_obj(path); },
              ThrowsInputError("cut.obj: line 3: expected 'v x y z', found 2 coordinates"));
}

TEST(ReadObj, RejectsFaceWithFewerThanThreeVertices) {
  TempDir dir;
  const auto path = dir.write("edge.obj", "v 0 0 0\nv 1 0 0\nf 1 2\n");
  EXPECT_THAT([&] { read_obj(path); },
              ThrowsInputError("edge.obj: line 3: a face needs at least 3 vertices, found 2"));
}

TEST(ReadObj, RejectsFreeFormGeometryStatements) {
  TempDir dir;
  const auto path = dir.write("curve.obj", "v 0 0 0\ncstype bspline\n");
  EXPECT_THAT([&] { read_obj(path); },
              ThrowsInputError("curve.obj: line 2: unsupported OBJ statement 'cstype' (expected v, "
                               "f, or one of vt vn vp mtllib usemtl o g s l)"));
}

TEST(ReadObj, RejectsRandomBytes) {
  TempDir dir;
  const auto path = dir.write("noise.obj", random_bytes(7, 4096));
  EXPECT_THAT([&] { read_obj(path); }, ThrowsInputError("noise.obj: line 1: unsupported OBJ "
                                                        "statement "
                                                        "'\\x13:\\xc7Qp\\xfa\\xb9t\\xfaN\\x89C\\x80"
                                                        "\\x16\\x12kD\\x04\\x7f\\x87\\xad\\xde\\xcd"
                                                        "Tad\\x10\\xacI\\xac\\xe8\\xb16Xs\\xed\\xee"
                                                        "C\\x06\\xc0...' (expected v, f, or one of "
                                                        "vt vn vp mtllib usemtl o g s l)"));
}

TEST(ReadObj, ReportsAMissingFile) {
  TempDir dir;
  const auto path = dir.path() / "absent.obj";
  EXPECT_THAT([&] { read_obj(path); },
              ThrowsInputError("absent.obj: cannot open (No such file or directory)"));
}

}  // namespace
}  // namespace softbench
