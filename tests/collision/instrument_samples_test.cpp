// SPDX-License-Identifier: MIT
#include "collision/instrument_samples.h"

#include "geometry/mesh_measures.h"
#include "tests/collision/bvh_test_meshes.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <numbers>
#include <vector>

namespace softbench::collision {
namespace {

using test::icosphere;

// A capped cylinder along z with two rings of `segments` vertices (at z = 0 and `length`) and a
// centre on each cap: its sides are long thin triangles, a rod tool's usual tessellation.
TriMesh rod(int segments, double radius, double length) {
  TriMesh mesh;
  mesh.vertices.resize(3, 2 * segments + 2);
  for (int k = 0; k < segments; ++k) {
    const double angle = 2.0 * std::numbers::pi * k / segments;
    for (int ring = 0; ring < 2; ++ring) {
      mesh.vertices.col(ring * segments + k) << radius * std::cos(angle), radius * std::sin(angle),
          ring * length;
    }
  }
  const int bottom = 2 * segments, top = 2 * segments + 1;
  mesh.vertices.col(bottom) << 0.0, 0.0, 0.0;
  mesh.vertices.col(top) << 0.0, 0.0, length;
  mesh.triangles.resize(3, 4 * segments);
  for (int k = 0; k < segments; ++k) {
    const int a = k, b = (k + 1) % segments, c = segments + k, d = segments + (k + 1) % segments;
    mesh.triangles.col(4 * k) << a, b, d;
    mesh.triangles.col(4 * k + 1) << a, d, c;
    mesh.triangles.col(4 * k + 2) << bottom, b, a;
    mesh.triangles.col(4 * k + 3) << top, c, d;
  }
  return mesh;
}

double nearest_sample(const Eigen::Matrix3Xd& samples, const Eigen::Vector3d& p) {
  return std::sqrt((samples.colwise() - p).colwise().squaredNorm().minCoeff());
}

struct Case {
  TriMesh mesh;
  double spacing;  ///< m
};

std::vector<Case> cases() {
  return {{icosphere(2, 0.01), 1e-3},          // a ball's tip, edges about 3 mm
          {rod(24, 0.003, 0.16), 0.00475572},  // the probe's shaft beside the liver
          {test::box_surface(2, {0.02, 0.01, 0.004}), 1.5e-3}};  // a blunt tool's faces
}

// No tissue triangle passes between the points: every point of the tool's surface (a grid of
// 24 per side on each triangle) is within spacing / sqrt(3) of one, the cover a plain grid of
// step `spacing` gives.
TEST(InstrumentSamples, CoverEveryPointOfTheSurfaceWithinTheSpacingOverRootThree) {
  for (const Case& c : cases()) {
    const Eigen::Matrix3Xd samples = instrument_samples(c.mesh, c.spacing);
    const double cover = c.spacing / std::sqrt(3.0);
    double farthest = 0.0;
    constexpr int kProbes = 24;
    for (Eigen::Index t = 0; t < c.mesh.triangles.cols(); ++t) {
      const Eigen::Vector3d a = c.mesh.vertices.col(c.mesh.triangles(0, t));
      const Eigen::Vector3d b = c.mesh.vertices.col(c.mesh.triangles(1, t));
      const Eigen::Vector3d d = c.mesh.vertices.col(c.mesh.triangles(2, t));
      for (int i = 0; i <= kProbes; ++i) {
        for (int j = 0; i + j <= kProbes; ++j) {
          const Eigen::Vector3d p = a + (static_cast<double>(i) / kProbes) * (b - a)
                                    + (static_cast<double>(j) / kProbes) * (d - a);
          farthest = std::max(farthest, nearest_sample(samples, p));
        }
      }
    }
    EXPECT_LE(farthest, cover * (1.0 + 1e-12)) << samples.cols() << " samples";
  }
}

// Every vertex is a sample (the mesh's own resolution of a rounded tip), and no other sample is
// nearer than the separation to any sample: the points a search is paid for are not wasted.
TEST(InstrumentSamples, KeepEveryVertexAndSpaceTheOtherPointsBySeparation) {
  for (const Case& c : cases()) {
    const Eigen::Matrix3Xd samples = instrument_samples(c.mesh, c.spacing);
    const Eigen::Index vertices = c.mesh.vertices.cols();
    ASSERT_GE(samples.cols(), vertices);
    EXPECT_TRUE(samples.leftCols(vertices) == c.mesh.vertices)
        << "the vertices come first, as they are";
    const double separation = kSampleSeparation * c.spacing;
    for (Eigen::Index i = vertices; i < samples.cols(); ++i) {
      for (Eigen::Index j = 0; j < samples.cols(); ++j) {
        if (j != i) {
          ASSERT_GE((samples.col(i) - samples.col(j)).norm(), separation * (1.0 - 1e-12))
              << "samples " << i << " and " << j;
        }
      }
    }
  }
}

// On a rod of long thin triangles the count is what the separation allows, not what a grid per
// triangle made: disks of half the separation around the samples that are not vertices do not
// overlap, so they number at most the surface's area over a disk's (with a quarter more for the
// curvature and the caps' rims).
TEST(InstrumentSamples, NumberAtMostWhatTheSeparationAllowsOnALongThinTriangulation) {
  const TriMesh mesh = rod(24, 0.003, 0.16);
  const double spacing = 0.00475572;
  const Eigen::Matrix3Xd samples = instrument_samples(mesh, spacing);
  const double disk = std::numbers::pi * std::pow(0.5 * kSampleSeparation * spacing, 2);
  const double allowed =
      static_cast<double>(mesh.vertices.cols()) + 1.25 * surface_area(mesh) / disk;
  EXPECT_LE(static_cast<double>(samples.cols()), allowed);
  // A grid of step `spacing` on each triangle, as the points were made before: (n + 1)(n + 2) / 2
  // a triangle less its corners, n its longest side over the spacing.
  double grid = static_cast<double>(mesh.vertices.cols());
  for (Eigen::Index t = 0; t < mesh.triangles.cols(); ++t) {
    double longest = 0.0;
    for (int k = 0; k < 3; ++k) {
      longest = std::max(longest, (mesh.vertices.col(mesh.triangles(k, t))
                                   - mesh.vertices.col(mesh.triangles((k + 1) % 3, t)))
                                      .norm());
    }
    const double n = std::ceil(longest / spacing);
    grid += 0.5 * (n + 1.0) * (n + 2.0) - 3.0;
  }
  EXPECT_LT(static_cast<double>(samples.cols()), 0.5 * grid);
}

}  // namespace
}  // namespace softbench::collision
