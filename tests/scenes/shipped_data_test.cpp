// SPDX-License-Identifier: MIT
// The meshes the project ships (made by `softbench mesh liver`) are what README.md describes
// ("The shipped liver"): thesis-sized, closed, valid, and refinements that really are ~4x and ~16x.
#include "scenes/shipped_data.h"

#include "geometry/mesh_io.h"
#include "geometry/mesh_measures.h"
#include "geometry/mesh_topology.h"
#include "geometry/mesh_validation.h"

#include <gtest/gtest.h>

namespace softbench::scenes {
namespace {

struct ShippedLiver {
  TetMesh mesh;
  ValidationReport report;
};

ShippedLiver load(std::string_view name) {
  ValidationReport report;
  TetMesh mesh = make_tet_mesh(read_mesh(shipped_data_file(name)), &report);
  return {std::move(mesh), std::move(report)};
}

TEST(ShippedLiver, IsThesisSizedValidAndClosed) {
  const ShippedLiver liver = load("liver.msh");
  EXPECT_GE(liver.mesh.num_vertices(), 1000);
  EXPECT_LE(liver.mesh.num_vertices(), 1600);
  EXPECT_GE(liver.mesh.num_tets(), 3500);
  EXPECT_LE(liver.mesh.num_tets(), 5500);
  EXPECT_EQ(liver.report.reoriented_tets, 0);
  EXPECT_TRUE(liver.report.problems.empty());
  const SurfaceTopology boundary =
      surface_topology(boundary_triangles(liver.mesh.tets()), liver.mesh.num_vertices());
  EXPECT_TRUE(boundary.closed_manifold());
  EXPECT_TRUE(boundary.oriented());
  EXPECT_EQ(boundary.euler_characteristic, 2);
  EXPECT_EQ(boundary.components, 1);
  // About 20 x 15 x 10 cm, in metres.
  const Eigen::Matrix<double, 3, 2> box = bounding_box(liver.mesh.rest_positions());
  const Eigen::Vector3d size = box.col(1) - box.col(0);
  EXPECT_NEAR(size.x(), 0.20, 0.03);
  EXPECT_NEAR(size.y(), 0.15, 0.03);
  EXPECT_NEAR(size.z(), 0.10, 0.03);
}

TEST(ShippedLiver, RefinementsHaveAboutFourAndSixteenTimesTheTetsAndTheSameVolume) {
  const ShippedLiver base = load("liver.msh");
  const ShippedLiver x4 = load("liver_x4.msh");
  const ShippedLiver x16 = load("liver_x16.msh");
  const double ratio4 = static_cast<double>(x4.mesh.num_tets()) / base.mesh.num_tets();
  const double ratio16 = static_cast<double>(x16.mesh.num_tets()) / base.mesh.num_tets();
  EXPECT_NEAR(ratio4, 4.0, 1.0);
  EXPECT_NEAR(ratio16, 16.0, 4.0);
  // Finer surfaces resolve the same organ: volumes agree within 2%.
  EXPECT_NEAR(mesh_volume(x4.mesh) / mesh_volume(base.mesh), 1.0, 0.02);
  EXPECT_NEAR(mesh_volume(x16.mesh) / mesh_volume(base.mesh), 1.0, 0.02);
  EXPECT_EQ(x4.report.reoriented_tets + x16.report.reoriented_tets, 0);
}

TEST(ShippedInstrument, IsAClosedOutwardSurfaceOfThesisSize) {
  const TriMesh probe = make_closed_surface(read_mesh(shipped_data_file("instrument_probe.obj")));
  EXPECT_NEAR(probe.num_vertices(), 628, 10);
  EXPECT_EQ(probe.num_triangles(), 1248);
  EXPECT_GT(enclosed_volume(probe), 0.0);
}

}  // namespace
}  // namespace softbench::scenes
