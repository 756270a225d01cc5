// SPDX-License-Identifier: MIT
#include "meshgen/liver_pipeline.h"

#include "geometry/mesh_measures.h"
#include "geometry/mesh_topology.h"
#include "geometry/mesh_validation.h"

#include <gtest/gtest.h>

namespace softbench::meshgen {
namespace {

LiverPipelineOptions base_resolution_only() {
  LiverPipelineOptions options;
  options.resolutions = {default_liver_resolutions().front()};
  return options;
}

TEST(LiverPipeline, IsDeterministic) {
  const LiverPipelineResult first = run_liver_pipeline(base_resolution_only());
  const LiverPipelineResult second = run_liver_pipeline(base_resolution_only());
  ASSERT_EQ(first.meshes.size(), 1u);
  EXPECT_EQ(first.meshes[0].volume.vertices, second.meshes[0].volume.vertices);
  EXPECT_EQ(first.meshes[0].volume.tetrahedra, second.meshes[0].volume.tetrahedra);
}

TEST(LiverPipeline, MakesAThesisSizedValidLiver) {
  const LiverPipelineResult result = run_liver_pipeline(base_resolution_only());
  const LiverMeshes& liver = result.meshes.front();
  // Segmentation had work to do: the noise made specks outside the organ.
  EXPECT_GT(result.stats.islands_removed, 0);
  // The smoothed marching-cubes surface is one closed sphere-like shell.
  const SurfaceTopology smoothed =
      surface_topology(result.smoothed_surface.triangles, result.smoothed_surface.num_vertices());
  EXPECT_TRUE(smoothed.closed_manifold());
  EXPECT_EQ(smoothed.euler_characteristic, 2);

  ValidationReport report;
  const TetMesh mesh = make_tet_mesh(liver.volume, &report);
  EXPECT_TRUE(report.problems.empty());
  EXPECT_GE(mesh.num_vertices(), 1000);
  EXPECT_LE(mesh.num_vertices(), 1600);
  EXPECT_GE(mesh.num_tets(), 3500);
  EXPECT_LE(mesh.num_tets(), 5500);
  EXPECT_GE(tet_quality(mesh.rest_positions(), mesh.tets()).min_dihedral_deg, 5.0);
  // TetGen kept the simplified surface, so the volumes agree to round-off.
  EXPECT_NEAR(mesh_volume(mesh), enclosed_volume(liver.surface), 1e-12);
  // About 1.3 L: a realistic adult liver.
  EXPECT_NEAR(mesh_volume(mesh), 1.3e-3, 0.3e-3);
}

}  // namespace
}  // namespace softbench::meshgen
