// SPDX-License-Identifier: MIT
#include "harness/report/mesh_info.h"

#include "tests/test_meshes.h"
#include "tests/test_tolerances.h"

#include <gmock/gmock.h>
#include <gtest/gtest.h>

#include <limits>

namespace softbench::harness {
namespace {

using ::testing::HasSubstr;

TEST(MeshInfo, CountsVerticesTetsFacesAndEdgesOfACube) {
  const MeshInfo info = inspect_mesh(test::box_tets(1, 1, 1));
  EXPECT_EQ(info.vertices, 8);
  EXPECT_EQ(info.tetrahedra, 6);
  EXPECT_EQ(info.triangles, 12);  // the boundary: two per cube face
  EXPECT_TRUE(info.triangles_from_boundary);
  EXPECT_EQ(info.faces, 18);  // 12 boundary + 6 interior
  EXPECT_EQ(info.edges, 19);  // 12 cube edges + 6 face diagonals + the main diagonal
  ASSERT_TRUE(info.volume.has_value());
  EXPECT_NEAR(*info.volume, 1.0, test::kRoundoff);
  EXPECT_TRUE(info.surface.closed_manifold());
  EXPECT_TRUE(info.usable());
  EXPECT_TRUE(info.problems.empty());
}

TEST(MeshInfo, JsonHasTheDocumentedKeys) {
  const nlohmann::json json = to_json(inspect_mesh(test::box_tets(2, 1, 1, 2.0, 1.0, 1.0)));
  for (const char* key : {"vertices", "triangles", "tetrahedra", "bbox", "volume", "problems",
                          "quality", "surface", "faces", "edges"}) {
    EXPECT_TRUE(json.contains(key)) << key;
  }
  EXPECT_EQ(json["tetrahedra"], 12);
  EXPECT_EQ(json["bbox"]["max"][0], 2.0);
  EXPECT_TRUE(json["problems"].empty());
}

TEST(MeshInfo, TextStartsEachCountOnItsOwnLine) {
  const std::string text = to_text(inspect_mesh(test::single_tet()));
  EXPECT_THAT(text, HasSubstr("\nvertices: 4\n"));
  EXPECT_THAT(text, HasSubstr("\ntriangles: 4 (tet boundary)\n"));
  EXPECT_THAT(text, HasSubstr("\ntetrahedra: 1\n"));
  EXPECT_THAT(text, HasSubstr("problems: none"));
}

TEST(MeshInfo, ReportsAnOpenSurfaceAsAWarningAndKeepsItUsable) {
  MeshData open = test::cube_surface();
  open.triangles.conservativeResize(3, 11);
  const MeshInfo info = inspect_mesh(open);
  EXPECT_FALSE(info.surface.closed_manifold());
  EXPECT_FALSE(info.volume.has_value());
  EXPECT_TRUE(info.usable());
  ASSERT_FALSE(info.problems.empty());
  EXPECT_EQ(info.problems.front().severity, MeshProblem::Severity::kWarning);
}

TEST(MeshInfo, WarnsAboutAnInwardSurfaceAndSeparateComponents) {
  MeshData inward = test::cube_surface();
  inward.triangles.row(1).swap(inward.triangles.row(2));
  const MeshInfo info = inspect_mesh(inward);
  ASSERT_TRUE(info.volume.has_value());
  EXPECT_NEAR(*info.volume, -1.0, test::kRoundoff);
  EXPECT_TRUE(info.usable());
  EXPECT_THAT(to_text(info), HasSubstr("warning: surface: oriented inward"));

  MeshData two = test::cube_surface();
  two.vertices.conservativeResize(3, 16);
  two.vertices.rightCols(8) = two.vertices.leftCols(8).array() + 2.0;
  two.triangles.conservativeResize(3, 24);
  two.triangles.rightCols(12) = two.triangles.leftCols(12).array() + 8;
  EXPECT_THAT(to_text(inspect_mesh(two)), HasSubstr("warning: surface: 2 separate components"));
}

TEST(MeshInfo, IgnoresInteriorVerticesWhenTetsComeWithBoundaryTriangles) {
  MeshData gmsh_like = test::box_tets(2, 2, 2);
  gmsh_like.triangles = boundary_triangles(gmsh_like.tetrahedra);
  const MeshInfo info = inspect_mesh(gmsh_like);
  EXPECT_TRUE(info.problems.empty());  // the centre vertex is on no triangle, rightly
  EXPECT_FALSE(info.triangles_from_boundary);
  EXPECT_TRUE(info.surface.closed_manifold());
}

TEST(MeshInfo, MarksANonFiniteCoordinateAsAnError) {
  MeshData bad = test::single_tet();
  bad.vertices(1, 2) = std::numeric_limits<double>::quiet_NaN();
  const MeshInfo info = inspect_mesh(bad);
  EXPECT_FALSE(info.usable());
  EXPECT_THAT(to_text(info), HasSubstr("error: vertex 2"));
}

TEST(MeshInfo, CountsAnInvertedTetAsAWarningAndStillMeasuresTheVolume) {
  MeshData inverted = test::single_tet();
  std::swap(inverted.tetrahedra(0, 0), inverted.tetrahedra(1, 0));
  const MeshInfo info = inspect_mesh(inverted);
  EXPECT_TRUE(info.usable());
  ASSERT_TRUE(info.volume.has_value());
  EXPECT_NEAR(*info.volume, 1.0 / 6.0, test::kRoundoff);
  EXPECT_THAT(to_text(info), HasSubstr("inverted"));
}

}  // namespace
}  // namespace softbench::harness
