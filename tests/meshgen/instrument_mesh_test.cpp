// SPDX-License-Identifier: MIT
#include "meshgen/instrument_mesh.h"

#include "geometry/mesh_measures.h"
#include "geometry/mesh_topology.h"

#include <gtest/gtest.h>

namespace softbench::meshgen {
namespace {

TEST(ProbeInstrument, HasTheThesisTriangleCountAndIsAClosedOutwardSurface) {
  const TriMesh probe = make_probe_instrument();
  EXPECT_EQ(probe.num_vertices(), 626);
  EXPECT_EQ(probe.num_triangles(), 1248);
  const SurfaceTopology topology = surface_topology(probe.triangles, probe.num_vertices());
  EXPECT_TRUE(topology.closed_manifold());
  EXPECT_TRUE(topology.oriented());
  EXPECT_EQ(topology.euler_characteristic, 2);
  EXPECT_EQ(topology.components, 1);
  EXPECT_GT(enclosed_volume(probe), 0.0);
}

TEST(ProbeInstrument, IsAFiveMillimetreShaftAlongZ) {
  const InstrumentOptions options;
  const TriMesh probe = make_probe_instrument(options);
  const Eigen::Matrix<double, 3, 2> box = bounding_box(probe.vertices);
  EXPECT_NEAR(box(2, 0), 0.0, 1e-12);
  EXPECT_NEAR(box(2, 1), options.length, 1e-12);
  // The jaw bulge is 20% over the shaft radius; polygon vertices lie on the circle.
  EXPECT_NEAR(box(0, 1), 1.2 * options.shaft_radius, 0.01 * options.shaft_radius);
  // A cylinder of the shaft's radius and length bounds the volume within 15% (tips, bulge).
  const double cylinder = 3.14159265 * options.shaft_radius * options.shaft_radius * options.length;
  EXPECT_NEAR(enclosed_volume(probe) / cylinder, 1.0, 0.15);
}

}  // namespace
}  // namespace softbench::meshgen
