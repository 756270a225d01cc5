// SPDX-License-Identifier: MIT
#include "geometry/mesh_topology.h"

#include "geometry/mesh_measures.h"
#include "geometry/mesh_validation.h"
#include "tests/test_meshes.h"
#include "tests/test_tolerances.h"

#include <gtest/gtest.h>

#include <stdexcept>
#include <utility>
#include <vector>

namespace softbench {
namespace {

using test::box_tets;
using test::cube_five_tets;
using test::cube_surface;
using test::single_tet;

// The triangles of an n x m grid on a torus (both directions wrap around), as index triples only:
// V = n m, E = 3 n m, F = 2 n m, so the Euler characteristic is 0.
Eigen::Matrix3Xi torus_triangles(int n, int m) {
  const auto vertex = [&](int i, int j) { return (i % n) + n * (j % m); };
  Eigen::Matrix3Xi triangles(3, 2 * n * m);
  int t = 0;
  for (int j = 0; j < m; ++j) {
    for (int i = 0; i < n; ++i) {
      triangles.col(t++) << vertex(i, j), vertex(i + 1, j), vertex(i + 1, j + 1);
      triangles.col(t++) << vertex(i, j), vertex(i + 1, j + 1), vertex(i, j + 1);
    }
  }
  return triangles;
}

void expect_strictly_sorted_pairs(const Eigen::Matrix2Xi& edges) {
  for (Eigen::Index e = 0; e < edges.cols(); ++e) {
    EXPECT_LT(edges(0, e), edges(1, e)) << "edge " << e;
    if (e > 0) {
      EXPECT_LT(std::make_pair(edges(0, e - 1), edges(1, e - 1)),
                std::make_pair(edges(0, e), edges(1, e)))
          << "edge " << e;
    }
  }
}

TEST(BoundaryTriangles, OfAPositiveTetFaceOutward) {
  const TetMesh tet = make_tet_mesh(single_tet());
  const TriMesh surface{tet.rest_positions(), boundary_triangles(tet.tets())};

  EXPECT_EQ(surface.num_triangles(), 4);
  EXPECT_NEAR(enclosed_volume(surface), 1.0 / 6.0, test::kRoundoff);
}

TEST(BoundaryTriangles, LeaveOutFacesSharedByTwoTets) {
  // The central tet of the five-tet cube touches the boundary only along edges.
  const TetMesh cube = make_tet_mesh(cube_five_tets());
  const TriMesh surface{cube.rest_positions(), boundary_triangles(cube.tets())};

  EXPECT_EQ(surface.num_triangles(), 12);
  EXPECT_NEAR(enclosed_volume(surface), 1.0, test::kRoundoff);
  EXPECT_NEAR(surface_area(surface), 6.0, test::kRoundoff);
}

TEST(BoundaryTriangles, DoNotDependOnTetOrderOrWhichVertexComesFirst) {
  const TetMesh box = make_tet_mesh(box_tets(2, 2, 1));
  const Eigen::Matrix4Xi& tets = box.tets();
  // Reverse the tet order and cycle three vertices of each tet (an even permutation, so the
  // orientation stays positive).
  Eigen::Matrix4Xi shuffled(4, tets.cols());
  for (Eigen::Index t = 0; t < tets.cols(); ++t) {
    const auto tet = tets.col(tets.cols() - 1 - t);
    shuffled.col(t) << tet(1), tet(2), tet(0), tet(3);
  }

  EXPECT_EQ(boundary_triangles(shuffled), boundary_triangles(tets));
}

TEST(BoundarySurface, OfABoxIsAClosedOutwardSphereEnclosingTheTetVolume) {
  const int nx = 3, ny = 2, nz = 2;
  const TetMesh box = make_tet_mesh(box_tets(nx, ny, nz, 2.0, 1.0, 1.0));
  const TriMesh surface = boundary_surface(box);
  const SurfaceTopology topology = surface_topology(surface.triangles, surface.num_vertices());

  EXPECT_EQ(surface.num_triangles(), 2 * (2 * (nx * ny + ny * nz + nx * nz)));
  EXPECT_TRUE(topology.closed_manifold());
  EXPECT_TRUE(topology.oriented());
  EXPECT_EQ(topology.euler_characteristic, 2);
  EXPECT_EQ(topology.components, 1);
  EXPECT_EQ(topology.unreferenced_vertices, 0);
  EXPECT_NEAR(enclosed_volume(surface), 2.0, test::kRoundoff);
  EXPECT_NEAR(enclosed_volume(surface), mesh_volume(box), test::kRoundoff);
  EXPECT_NEAR(surface_area(surface), 2.0 * (2.0 * 1.0 + 1.0 * 1.0 + 2.0 * 1.0), test::kRoundoff);
}

TEST(BoundarySurface, KeepsOnlySurfaceVerticesInTetMeshOrder) {
  const int nx = 3, ny = 2, nz = 2;
  const TetMesh box = make_tet_mesh(box_tets(nx, ny, nz, 2.0, 1.0, 1.0));
  std::vector<int> tet_vertex_of;
  const TriMesh surface = boundary_surface(box, &tet_vertex_of);

  const int interior_vertices = (nx - 1) * (ny - 1) * (nz - 1);
  ASSERT_EQ(surface.num_vertices(), box.num_vertices() - interior_vertices);
  ASSERT_EQ(static_cast<int>(tet_vertex_of.size()), surface.num_vertices());
  for (int i = 0; i < surface.num_vertices(); ++i) {
    if (i > 0) {
      EXPECT_LT(tet_vertex_of[i - 1], tet_vertex_of[i]);
    }
    EXPECT_EQ(surface.vertices.col(i), box.rest_positions().col(tet_vertex_of[i])) << i;
  }
}

TEST(UniqueEdges, OfASingleTetAreItsSixEdges) {
  const Eigen::Matrix2Xi edges = unique_edges(single_tet().tetrahedra);

  EXPECT_EQ(edges.cols(), 6);
  expect_strictly_sorted_pairs(edges);
}

TEST(UniqueEdges, OfTheFiveTetCubeAreTheCubeEdgesAndSixFaceDiagonals) {
  const Eigen::Matrix2Xi edges = unique_edges(cube_five_tets().tetrahedra);

  EXPECT_EQ(edges.cols(), 12 + 6);
  expect_strictly_sorted_pairs(edges);
}

TEST(UniqueEdges, EdgeIndexFindsEveryEdgeAndWhereAnAbsentOneWouldGo) {
  const Eigen::Matrix2Xi edges = unique_edges(cube_five_tets().tetrahedra);
  for (Eigen::Index e = 0; e < edges.cols(); ++e) {
    EXPECT_EQ(edge_index(edges, edges(0, e), edges(1, e)), e);
  }
  EXPECT_EQ(edge_index(edges, -1, 0), 0);
  EXPECT_EQ(edge_index(edges, 1000, 1001), edges.cols());
}

TEST(UniqueEdges, OfTheCubeSurfaceAreTheCubeEdgesAndSixFaceDiagonals) {
  const Eigen::Matrix2Xi edges = unique_edges(cube_surface().triangles);

  EXPECT_EQ(edges.cols(), 12 + 6);
  expect_strictly_sorted_pairs(edges);
}

TEST(SurfaceTopology, OfTheCubeIsAClosedOrientedSphere) {
  const MeshData cube = cube_surface();
  const SurfaceTopology topology = surface_topology(cube.triangles, 8);

  EXPECT_TRUE(topology.closed_manifold());
  EXPECT_TRUE(topology.oriented());
  EXPECT_EQ(topology.boundary_edges, 0);
  EXPECT_EQ(topology.non_manifold_edges, 0);
  EXPECT_EQ(topology.misoriented_edges, 0);
  EXPECT_EQ(topology.components, 1);
  EXPECT_EQ(topology.euler_characteristic, 2);
  EXPECT_EQ(topology.unreferenced_vertices, 0);
}

TEST(SurfaceTopology, OfATorusHasEulerCharacteristicZero) {
  const SurfaceTopology topology = surface_topology(torus_triangles(5, 4), 5 * 4);

  EXPECT_TRUE(topology.closed_manifold());
  EXPECT_TRUE(topology.oriented());
  EXPECT_EQ(topology.euler_characteristic, 0);
  EXPECT_EQ(topology.components, 1);
}

TEST(SurfaceTopology, CountsTheThreeOpenEdgesOfACubeMissingATriangle) {
  MeshData cube = cube_surface();
  cube.triangles.conservativeResize(3, 11);
  const SurfaceTopology topology = surface_topology(cube.triangles, 8);

  EXPECT_FALSE(topology.closed_manifold());
  EXPECT_EQ(topology.boundary_edges, 3);
  EXPECT_EQ(topology.euler_characteristic, 1);  // a disc
}

TEST(SurfaceTopology, CountsAnEdgeSharedByThreeTrianglesAsNonManifold) {
  Eigen::Matrix3Xi fan(3, 3);
  fan << 0, 1, 0,  //
      1, 0, 1,     //
      2, 3, 4;
  const SurfaceTopology topology = surface_topology(fan, 5);

  EXPECT_EQ(topology.non_manifold_edges, 1);
  EXPECT_EQ(topology.boundary_edges, 6);
  EXPECT_FALSE(topology.closed_manifold());
}

TEST(SurfaceTopology, CountsTheEdgesOfAFlippedTriangleAsMisoriented) {
  MeshData cube = cube_surface();
  std::swap(cube.triangles(1, 0), cube.triangles(2, 0));
  const SurfaceTopology topology = surface_topology(cube.triangles, 8);

  EXPECT_TRUE(topology.closed_manifold());
  EXPECT_FALSE(topology.oriented());
  EXPECT_EQ(topology.misoriented_edges, 3);
}

TEST(SurfaceTopology, CountsComponentsAndUnreferencedVertices) {
  // Two cubes sharing no vertex, in a vertex array with two unused vertices between them.
  const MeshData cube = cube_surface();
  Eigen::Matrix3Xi triangles(3, 24);
  triangles << cube.triangles, (cube.triangles.array() + 10).matrix();
  const SurfaceTopology topology = surface_topology(triangles, 18);

  EXPECT_EQ(topology.components, 2);
  EXPECT_EQ(topology.euler_characteristic, 4);
  EXPECT_EQ(topology.unreferenced_vertices, 2);
  EXPECT_TRUE(topology.closed_manifold());
}

TEST(SurfaceTopology, IgnoresTrianglesWithARepeatedVertex) {
  // A collapsed triangle is a segment: it must not make a closed surface look open.
  const MeshData cube = cube_surface();
  Eigen::Matrix3Xi triangles(3, 13);
  triangles << cube.triangles, Eigen::Vector3i(0, 2, 2);
  const SurfaceTopology topology = surface_topology(triangles, 8);

  EXPECT_TRUE(topology.closed_manifold());
  EXPECT_TRUE(topology.oriented());
  EXPECT_EQ(topology.euler_characteristic, 2);
}

TEST(SurfaceTopology, RejectsVertexIndicesOutOfRange) {
  EXPECT_THROW(surface_topology(cube_surface().triangles, 7), std::out_of_range);
}

}  // namespace
}  // namespace softbench
