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

// Five nodes numbered 1..5: a tet, a boundary triangle, a line and a point, as SOFA's liver.msh
// and liver2.msh are written (MSH 1).
constexpr const char* kVersion1 =
    "$NOD\n"
    "5\n"
    "1 0 0 0\n"
    "2 1 0 0\n"
    "3 0 1 0\n"
    "4 0 0 1\n"
    "5 0.25 0.25 0.25\n"
    "$ENDNOD\n"
    "$ELM\n"
    "4\n"
    "1 15 0 1 1 5\n"
    "2 1 0 1 2 1 2\n"
    "3 2 0 1 3 1 3 2\n"
    "4 4 1 1 4 1 2 3 4\n"
    "$ENDELM\n";

TEST(ReadMsh, ReadsVersion1KeepingTrianglesAndTetsAndSkippingPointsAndLines) {
  TempDir dir;
  const MeshData mesh = read_msh(dir.write("v1.msh", kVersion1));
  ASSERT_EQ(mesh.vertices.cols(), 5);
  ASSERT_EQ(mesh.triangles.cols(), 1);
  ASSERT_EQ(mesh.tetrahedra.cols(), 1);
  EXPECT_EQ(mesh.vertices.col(4), Eigen::Vector3d(0.25, 0.25, 0.25));
  EXPECT_EQ(mesh.triangles.col(0), Eigen::Vector3i(0, 2, 1));
  EXPECT_EQ(mesh.tetrahedra.col(0), Eigen::Vector4i(0, 1, 2, 3));
}

TEST(ReadMsh, RemapsNonContiguousNodeTags) {
  TempDir dir;
  // Tags as in SOFA's liver2.msh: 2, 9, 17, ... remapped to 0, 1, 2, ... in file order.
  const auto path = dir.write("tags.msh",
                              "$NOD\n4\n"
                              "17 0 0 0\n"
                              "2 1 0 0\n"
                              "9 0 1 0\n"
                              "22 0 0 1\n"
                              "$ENDNOD\n"
                              "$ELM\n1\n"
                              "1 4 0 0 4 2 9 17 22\n"
                              "$ENDELM\n");
  const MeshData mesh = read_msh(path);
  ASSERT_EQ(mesh.tetrahedra.cols(), 1);
  EXPECT_EQ(mesh.tetrahedra.col(0), Eigen::Vector4i(1, 2, 0, 3));
  EXPECT_EQ(mesh.vertices.col(1), Eigen::Vector3d(1, 0, 0));
}

TEST(ReadMsh, ReadsVersion22WithTagsAndSkipsUnknownSections) {
  TempDir dir;
  const auto path = dir.write("v22.msh",
                              "$MeshFormat\n2.2 0 8\n$EndMeshFormat\n"
                              "$PhysicalNames\n1\n3 1 \"liver\"\n$EndPhysicalNames\n"
                              "$Nodes\n4\n"
                              "1 0 0 0\n2 1 0 0\n3 0 1 0\n4 0 0 1\n"
                              "$EndNodes\n"
                              "$Elements\n3\n"
                              "1 15 2 0 1 1\n"
                              "2 2 2 0 7 1 3 2\n"
                              "3 4 3 1 1 0 1 2 3 4\n"
                              "$EndElements\n"
                              "$NodeData\n1\n\"u\"\n1\n0.0\n3\n0\n1\n4\n1 0\n2 0\n3 0\n4 0\n"
                              "$EndNodeData\n");
  const MeshData mesh = read_msh(path);
  EXPECT_EQ(mesh.vertices.cols(), 4);
  ASSERT_EQ(mesh.triangles.cols(), 1);
  ASSERT_EQ(mesh.tetrahedra.cols(), 1);
  EXPECT_EQ(mesh.triangles.col(0), Eigen::Vector3i(0, 2, 1));
  EXPECT_EQ(mesh.tetrahedra.col(0), Eigen::Vector4i(0, 1, 2, 3));
}

TEST(ReadMsh, ReadsVersion41EntityBlocksAndSkipsEntities) {
  TempDir dir;
  const auto path = dir.write("v41.msh",
                              "$MeshFormat\n4.1 0 8\n$EndMeshFormat\n"
                              "$Entities\n1 0 0 1\n1 0 0 0\n1 0 0 0 1 1 1 0 0\n"
                              "1 0 0 0 1 1 1 0 0\n$EndEntities\n"
                              "$Nodes\n"
                              "2 5 10 50\n"
                              "0 1 0 1\n"
                              "10\n"
                              "0 0 0\n"
                              "2 1 1 4\n"
                              "20\n30\n40\n50\n"
                              "1 0 0 0.5 0\n"  // parametric: x y z u v
                              "0 1 0 0 0.5\n"
                              "0 0 1 0 0\n"
                              "0.25 0.25 0 0.25 0.25\n"
                              "$EndNodes\n"
                              "$Elements\n"
                              "3 4 1 4\n"
                              "0 1 15 1\n"
                              "1 10\n"
                              "2 1 2 2\n"
                              "2 10 20 50\n"
                              "3 20 30 50\n"
                              "3 1 4 1\n"
                              "4 10 20 30 40\n"
                              "$EndElements\n");
  const MeshData mesh = read_msh(path);
  ASSERT_EQ(mesh.vertices.cols(), 5);
  ASSERT_EQ(mesh.triangles.cols(), 2);
  ASSERT_EQ(mesh.tetrahedra.cols(), 1);
  EXPECT_EQ(mesh.vertices.col(4), Eigen::Vector3d(0.25, 0.25, 0));
  EXPECT_EQ(mesh.triangles.col(1), Eigen::Vector3i(1, 2, 4));
  EXPECT_EQ(mesh.tetrahedra.col(0), Eigen::Vector4i(0, 1, 2, 3));
}

TEST(ReadMsh, RejectsFewerNodesThanTheCountSays) {
  TempDir dir;
  std::string content = kVersion1;
  content.replace(content.find("5 0.25 0.25 0.25\n"), 17, "");
  const auto path = dir.write("liver.msh", content);
  EXPECT_THAT([&] { read_msh(path); },
              ThrowsInputError("liver.msh: line 7: expected 5 nodes in $NOD, found 4 before "
                               "$ENDNOD"));
}

TEST(ReadMsh, RejectsMoreNodesThanTheCountSays) {
  TempDir dir;
  std::string content = kVersion1;
  content.replace(content.find("5\n"), 2, "4\n");
  const auto path = dir.write("extra.msh", content);
  EXPECT_THAT([&] { read_msh(path); },
              ThrowsInputError("extra.msh: line 7: expected the end of $NOD after 4 nodes, found "
                               "'5'"));
}

TEST(ReadMsh, RejectsAFileTruncatedInsideElements) {
  TempDir dir;
  const std::string content = kVersion1;
  const auto path = dir.write("cut.msh", content.substr(0, content.find("3 2 0 1 3")));
  EXPECT_THAT([&] { read_msh(path); },
              ThrowsInputError("cut.msh: line 12: expected 4 elements in $ELM, found 2 before end "
                               "of file"));
}

TEST(ReadMsh, RejectsElementReferringToAnUndefinedNode) {
  TempDir dir;
  std::string content = kVersion1;
  content.replace(content.find("4 4 1 1 4 1 2 3 4"), 17, "4 4 1 1 4 1 2 3 9");
  const auto path = dir.write("dangling.msh", content);
  EXPECT_THAT([&] { read_msh(path); },
              ThrowsInputError("dangling.msh: line 14: element 4 refers to node 9, which $NOD does "
                               "not define"));
}

TEST(ReadMsh, RejectsNanCoordinate) {
  TempDir dir;
  std::string content = kVersion1;
  content.replace(content.find("3 0 1 0"), 7, "3 0 NaN 0");
  const auto path = dir.write("nan.msh", content);
  EXPECT_THAT([&] { read_msh(path); },
              ThrowsInputError("nan.msh: line 5: node 3 has a non-finite coordinate (NaN)"));
}

TEST(ReadMsh, RejectsSecondOrderTetrahedra) {
  TempDir dir;
  const auto path = dir.write("tet10.msh",
                              "$MeshFormat\n2.2 0 8\n$EndMeshFormat\n"
                              "$Nodes\n1\n1 0 0 0\n$EndNodes\n"
                              "$Elements\n1\n1 11 2 0 1 1 1 1 1 1 1 1 1 1 1\n$EndElements\n");
  EXPECT_THAT([&] { read_msh(path); },
              ThrowsInputError("tet10.msh: line 10: unsupported element type 11 (10-node "
                               "second-order tetrahedron); expected 2 (triangle) or 4 "
                               "(tetrahedron), or 1 (line) or 15 (point), which are skipped"));
}

TEST(ReadMsh, RejectsElementLineWithTheWrongNumberOfNodes) {
  TempDir dir;
  std::string content = kVersion1;
  content.replace(content.find("4 4 1 1 4 1 2 3 4"), 17, "4 4 1 1 4 1 2 3");
  const auto path = dir.write("short.msh", content);
  EXPECT_THAT([&] { read_msh(path); }, ThrowsInputError("short.msh: line 14: expected 9 values "
                                                        "(elm-number elm-type reg-phys reg-elem "
                                                        "number-of-nodes and 4 node numbers), "
                                                        "found 8"));
}

TEST(ReadMsh, RejectsDuplicateNodeTags) {
  TempDir dir;
  std::string content = kVersion1;
  content.replace(content.find("2 1 0 0"), 7, "1 1 0 0");
  const auto path = dir.write("twice.msh", content);
  EXPECT_THAT([&] { read_msh(path); },
              ThrowsInputError("twice.msh: line 4: node 1 is defined twice"));
}

TEST(ReadMsh, RejectsBinaryMsh) {
  TempDir dir;
  const auto path = dir.write(
      "binary.msh", "$MeshFormat\n4.1 1 8\n" + random_bytes(3, 64) + "\n$EndMeshFormat\n");
  EXPECT_THAT([&] { read_msh(path); },
              ThrowsInputError("binary.msh: line 2: binary MSH not supported (file-type 1); save "
                               "the mesh as ASCII"));
}

TEST(ReadMsh, RejectsUnsupportedVersions) {
  TempDir dir;
  const auto path = dir.write("v3.msh", "$MeshFormat\n3.0 0 8\n$EndMeshFormat\n");
  EXPECT_THAT([&] { read_msh(path); },
              ThrowsInputError("v3.msh: line 2: unsupported MSH version '3.0' (expected 1, 2.2 or "
                               "4.1)"));
}

TEST(ReadMsh, RejectsAHugeNodeCountBeforeAllocating) {
  TempDir dir;
  const auto path = dir.write("huge.msh", "$NOD\n2000000000\n1 0 0 0\n$ENDNOD\n");
  EXPECT_THAT(
      [&] { read_msh(path); },
      ThrowsInputError("huge.msh: line 2: truncated file or wrong count: 2000000000 nodes cannot "
                       "fit in the 16 bytes left in the file"));
}

TEST(ReadMsh, RejectsRandomBytes) {
  TempDir dir;
  const auto path = dir.write("noise.msh", random_bytes(11, 4096));
  EXPECT_THAT([&] { read_msh(path); },
              ThrowsInputError("noise.msh: line 1: expected $MeshFormat (MSH 2.2, 4.1) or $NOD "
                               "(MSH 1) at the start of a Gmsh file, found "
                               "'.\\x11\\x04\\xaav1\\xb9\\xedk\\x1a|9\\x03\\xe5|\\xd3\\xf1\\x17\\xd"
                               "9\\xe3\\xba\\xb6\\x1b\\x84\\xe4\\xc9\\xdb\\x96*\\xbc\\xa1\\xac\\x05"
                               "\\xf8\\x1d\\xfdP\\xc7(\\x06...'"));
}

TEST(ReadMsh, RejectsAnEmptyFile) {
  TempDir dir;
  const auto path = dir.write("empty.msh", "");
  EXPECT_THAT([&] { read_msh(path); }, ThrowsInputError("empty.msh: line 1: empty file; expected "
                                                        "$MeshFormat (MSH 2.2, 4.1) or $NOD (MSH 1)"));
}

}  // namespace
}  // namespace softbench
