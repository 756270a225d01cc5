// SPDX-License-Identifier: MIT
#include "harness/report/mesh_info.h"

#include "tests/test_meshes.h"
#include "tests/test_tolerances.h"

#include <gmock/gmock.h>
#include <gtest/gtest.h>

#include <array>
#include <limits>
#include <string>
#include <utility>
#include <vector>

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

// --- self-intersection --------------------------------------------------------------------------

// The unit cube's surface and a copy shifted by `shift`, as one surface (two components).
MeshData two_cubes(const Eigen::Vector3d& shift) {
  MeshData two = test::cube_surface();
  two.vertices.conservativeResize(3, 16);
  two.vertices.rightCols(8) = two.vertices.leftCols(8).colwise() + shift;
  two.triangles.conservativeResize(3, 24);
  two.triangles.rightCols(12) = two.triangles.leftCols(12).array() + 8;
  return two;
}

// Triangles given by their corners, each with its own three vertices (nothing welded: shared
// corners are shared by position).
SelfIntersections self_intersections_of(const std::vector<std::array<Eigen::Vector3d, 3>>& tris) {
  Eigen::Matrix3Xd vertices(3, 3 * tris.size());
  Eigen::Matrix3Xi triangles(3, tris.size());
  for (std::size_t t = 0; t < tris.size(); ++t) {
    for (int corner = 0; corner < 3; ++corner) {
      const auto index = static_cast<Eigen::Index>(3 * t) + corner;
      vertices.col(index) = tris[t][static_cast<std::size_t>(corner)];
      triangles(corner, static_cast<Eigen::Index>(t)) = static_cast<int>(index);
    }
  }
  return find_self_intersections(vertices, triangles);
}

int crossing_pairs(const Eigen::Vector3d& a0,
                   const Eigen::Vector3d& a1,
                   const Eigen::Vector3d& a2,
                   const Eigen::Vector3d& b0,
                   const Eigen::Vector3d& b1,
                   const Eigen::Vector3d& b2) {
  return self_intersections_of({{a0, a1, a2}, {b0, b1, b2}}).pairs;
}

TEST(MeshInfoSelfIntersection, FindsNoneOnAClosedCubeWhoseNeighboursOnlyTouch) {
  // Each triangle touches 9 others at shared vertices or edges, coplanar ones on each face.
  const MeshInfo info = inspect_mesh(test::cube_surface());
  EXPECT_EQ(info.self_intersecting_pairs, 0);
  EXPECT_TRUE(info.problems.empty());
  EXPECT_THAT(to_text(info), HasSubstr("problems: none"));
  EXPECT_EQ(to_json(info)["self_intersecting_pairs"], 0);
  // The same with every triangle on its own vertices: shared corners count by position.
  const MeshData cube = test::cube_surface();
  std::vector<std::array<Eigen::Vector3d, 3>> loose;
  for (Eigen::Index t = 0; t < cube.triangles.cols(); ++t) {
    loose.push_back({cube.vertices.col(cube.triangles(0, t)),
                     cube.vertices.col(cube.triangles(1, t)),
                     cube.vertices.col(cube.triangles(2, t))});
  }
  EXPECT_EQ(self_intersections_of(loose).pairs, 0);
  // And a subdivided box's boundary: many coplanar neighbours around each vertex.
  EXPECT_EQ(inspect_mesh(test::box_tets(3, 2, 2)).self_intersecting_pairs, 0);
}

TEST(MeshInfoSelfIntersection, FindsTwoInterpenetratingCubesMergedIntoOneSurface) {
  const MeshInfo info = inspect_mesh(two_cubes(Eigen::Vector3d(0.5, 0.5, 0.5)));
  // The corner the second cube pushes into the first crosses its three faces at the far corner
  // (x, y, z = 1): each face's two triangles against the second cube's triangles there.
  EXPECT_GT(info.self_intersecting_pairs, 0);
  EXPECT_FALSE(info.usable());
  const std::string text = to_text(info);
  EXPECT_THAT(text, HasSubstr("error: surface intersects itself: "
                              + std::to_string(info.self_intersecting_pairs) + " triangle pair"));
  EXPECT_THAT(text, HasSubstr("e.g. triangles "));
  // Apart, they do not intersect; face to face, they overlap (touching counts, as for TetGen).
  EXPECT_EQ(inspect_mesh(two_cubes(Eigen::Vector3d(2.0, 0.0, 0.0))).self_intersecting_pairs, 0);
  EXPECT_GT(inspect_mesh(two_cubes(Eigen::Vector3d(1.0, 0.0, 0.0))).self_intersecting_pairs, 0);
}

TEST(MeshInfoSelfIntersection, FindsASurfaceFoldedOverAlongAnEdge) {
  const Eigen::Vector3d o(0, 0, 0), x(1, 0, 0), y(0, 1, 0);
  // Sharing the edge x-y: flat and unfolded, folded up out of the plane, folded flat onto the
  // first triangle (same side of the edge, one plane: they overlap).
  EXPECT_EQ(crossing_pairs(o, x, y, x, Eigen::Vector3d(1, 1, 0), y), 0);
  EXPECT_EQ(crossing_pairs(o, x, y, x, Eigen::Vector3d(0.2, 0.2, 0.5), y), 0);
  EXPECT_EQ(crossing_pairs(o, x, y, x, Eigen::Vector3d(0.2, 0.2, 0.0), y), 1);
  // A folded strip inside a closed surface: the cube with one corner pushed through the opposite
  // face (vertex 7 at (1, 1, 1) moved to (0.5, 0.5, -0.5)).
  MeshData dented = test::cube_surface();
  dented.vertices.col(7) = Eigen::Vector3d(0.5, 0.5, -0.5);
  const MeshInfo info = inspect_mesh(dented);
  EXPECT_GT(info.self_intersecting_pairs, 0);
  EXPECT_FALSE(info.usable());
}

TEST(MeshInfoSelfIntersection, TellsTrianglesThatMeetAtAVertexFromOnesThatCrossThere) {
  const Eigen::Vector3d v(0, 0, 0), x(1, 0, 0), y(0, 1, 0);
  // Out of the plane, touching only at v.
  EXPECT_EQ(crossing_pairs(v, x, y, v, Eigen::Vector3d(-1, 0, 1), Eigen::Vector3d(0, -1, 1)), 0);
  // Through the plane at v only: the other triangle's interior meets the plane in v alone.
  EXPECT_EQ(crossing_pairs(v, x, y, v, Eigen::Vector3d(-1, -1, 1), Eigen::Vector3d(-1, -1, -1)), 0);
  // Piercing the first from v on: its edge opposite v passes through (0.3, 0.3, 0).
  EXPECT_EQ(crossing_pairs(v, x, y, v, Eigen::Vector3d(0.3, 0.3, -1), Eigen::Vector3d(0.3, 0.3, 1)),
            1);
  // The same, but its edge opposite v passes beside the first triangle: the two meet in a
  // segment from v to the first's far edge, which the second crosses.
  EXPECT_EQ(crossing_pairs(v, x, y, v, Eigen::Vector3d(2, 2, -1), Eigen::Vector3d(2, 2, 1)), 1);
  // In one plane: outside each other's angle at v, and overlapping.
  EXPECT_EQ(crossing_pairs(v, x, y, v, Eigen::Vector3d(-1, 0, 0), Eigen::Vector3d(0, -1, 0)), 0);
  EXPECT_EQ(crossing_pairs(v, x, y, v, Eigen::Vector3d(0.5, 0.1, 0), Eigen::Vector3d(0.1, 0.5, 0)),
            1);
  // In one plane along a common edge direction from v: they share the segment v-x.
  EXPECT_EQ(crossing_pairs(v, x, y, v, Eigen::Vector3d(2, 0, 0), Eigen::Vector3d(1, -1, 0)), 1);
  // Sharing v, with an edge from v lying in the first's plane but outside its angle.
  EXPECT_EQ(crossing_pairs(v, x, y, v, Eigen::Vector3d(-1, 0, 0), Eigen::Vector3d(0, -1, 1)), 0);
  // A duplicated triangle.
  EXPECT_EQ(crossing_pairs(v, x, y, y, v, x), 1);
}

TEST(MeshInfoSelfIntersection, ListsAFewExamplesAndCountsEveryPair) {
  // A fan of 8 triangles around the z axis, each pierced by one long needle triangle.
  std::vector<std::array<Eigen::Vector3d, 3>> tris;
  for (int i = 0; i < 8; ++i) {
    const double z = i;
    tris.push_back(
        {Eigen::Vector3d(-1, -1, z), Eigen::Vector3d(1, -1, z), Eigen::Vector3d(0, 1, z)});
  }
  tris.push_back(
      {Eigen::Vector3d(0, 0, -1), Eigen::Vector3d(0.01, 0, 9), Eigen::Vector3d(0, 0.01, 9)});
  const SelfIntersections found = self_intersections_of(tris);
  EXPECT_EQ(found.pairs, 8);
  ASSERT_EQ(found.examples.size(), 5u);
  EXPECT_EQ(found.examples.front(), std::make_pair(0, 8));
}

}  // namespace
}  // namespace softbench::harness
