// SPDX-License-Identifier: MIT
#include "meshgen/tetrahedralize.h"

#include "geometry/input_error.h"
#include "geometry/marching_cubes.h"
#include "geometry/mesh_measures.h"
#include "geometry/mesh_topology.h"
#include "geometry/mesh_validation.h"
#include "meshgen/surface_simplification.h"
#include "tests/test_meshes.h"
#include "tests/test_tolerances.h"

#include <gmock/gmock.h>
#include <gtest/gtest.h>

namespace softbench::meshgen {
namespace {

TriMesh cube() {
  const MeshData data = test::cube_surface();
  return {data.vertices, data.triangles};
}

TriMesh sphere_surface(double radius, double spacing) {
  ScalarGrid grid;
  const int n = static_cast<int>(2.6 * radius / spacing) + 1;
  grid.size = {n, n, n};
  grid.origin = Eigen::Vector3d::Constant(-1.3 * radius);
  grid.spacing = Eigen::Vector3d::Constant(spacing);
  grid.values.resize(static_cast<std::size_t>(n) * n * n);
  for (int k = 0; k < n; ++k) {
    for (int j = 0; j < n; ++j) {
      for (int i = 0; i < n; ++i) {
        grid.at(i, j, k) = static_cast<float>(radius - grid.position(i, j, k).norm());
      }
    }
  }
  return marching_cubes(grid, 0.0f);
}

TEST(Tetrahedralize, FillsACubeWithPositiveTetsOfExactlyItsVolumeUnderTheVolumeBound) {
  TetrahedralizeOptions options;
  options.max_volume = 0.01;
  // TetGen rejects Steiner points that encroach a preserved surface, and every candidate in a
  // two-triangles-per-face cube does: let it split the surface here.
  options.preserve_surface = false;
  MeshData volume = tetrahedralize(cube(), options);
  ValidationReport report;
  const TetMesh mesh = make_tet_mesh(volume, &report);
  EXPECT_EQ(report.reoriented_tets, 0);
  EXPECT_NEAR(mesh_volume(mesh), 1.0, test::kRoundoff);
  for (int t = 0; t < mesh.num_tets(); ++t) {
    const auto& tet = mesh.tets().col(t);
    const auto& x = mesh.rest_positions();
    EXPECT_LE(signed_tet_volume(x.col(tet(0)), x.col(tet(1)), x.col(tet(2)), x.col(tet(3))),
              options.max_volume * (1 + test::kRoundoff));
  }
  EXPECT_GE(mesh.num_tets(), 100);
  const SurfaceTopology boundary =
      surface_topology(boundary_triangles(mesh.tets()), mesh.num_vertices());
  EXPECT_TRUE(boundary.closed_manifold());
}

TEST(Tetrahedralize, PreservesTheInputSurfaceWhenAsked) {
  const TriMesh sphere = sphere_surface(1.0, 0.2);
  const MeshData volume = tetrahedralize(sphere, {});
  // -Y keeps every surface vertex (in order, first) and adds Steiner points only inside.
  ASSERT_GE(volume.vertices.cols(), sphere.vertices.cols());
  EXPECT_EQ(volume.vertices.leftCols(sphere.num_vertices()), sphere.vertices);
  EXPECT_EQ(volume.triangles.cols(), sphere.triangles.cols());
  EXPECT_NEAR(mesh_volume(make_tet_mesh(volume)), enclosed_volume(sphere), 1e-9);
}

TEST(Tetrahedralize, RejectsAnUnreachableQualityBound) {
  TetrahedralizeOptions options;
  options.radius_edge_ratio = 1.0;
  EXPECT_THROW(tetrahedralize(cube(), options), InputError);
}

TEST(Tetrahedralize, RejectsASelfIntersectingSurfaceWithoutCrashing) {
  // Two unit cubes overlapping by half: closed and manifold, but each cuts through the other.
  const TriMesh first = cube();
  TriMesh both;
  both.vertices.resize(3, 2 * first.num_vertices());
  both.vertices << first.vertices, (first.vertices.colwise() + Eigen::Vector3d(0.5, 0.5, 0.5));
  both.triangles.resize(3, 2 * first.num_triangles());
  both.triangles << first.triangles, (first.triangles.array() + first.num_vertices()).matrix();
  try {
    tetrahedralize(both, {});
    FAIL() << "expected InputError";
  } catch (const InputError& error) {
    EXPECT_THAT(error.what(), ::testing::HasSubstr("intersects itself"));
  }
}

TEST(SimplifySurface, ReachesTheTargetAndKeepsAClosedSurfaceAndItsVolume) {
  const TriMesh sphere = sphere_surface(1.0, 0.05);
  ASSERT_GT(sphere.num_vertices(), 3000);
  const TriMesh simplified = simplify_surface(sphere, 400);
  // The remesher reaches the target count within a few percent.
  EXPECT_NEAR(simplified.num_vertices(), 400, 20);
  const SurfaceTopology topology =
      surface_topology(simplified.triangles, simplified.num_vertices());
  EXPECT_TRUE(topology.closed_manifold());
  EXPECT_TRUE(topology.oriented());
  EXPECT_EQ(topology.euler_characteristic, 2);
  // Vertices stay on the input surface, so only the chords lose volume: a 400-vertex polyhedron
  // inscribed in a sphere (edges ~0.19 R) encloses about 1.5% less than the sphere.
  EXPECT_NEAR(enclosed_volume(simplified) / enclosed_volume(sphere), 1.0, 0.03);
}

}  // namespace
}  // namespace softbench::meshgen
