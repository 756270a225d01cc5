// SPDX-License-Identifier: MIT
#include "geometry/surface_smoothing.h"

#include "geometry/marching_cubes.h"
#include "geometry/mesh_measures.h"
#include "geometry/mesh_topology.h"
#include "tests/test_tolerances.h"

#include <Eigen/Geometry>
#include <gtest/gtest.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <map>
#include <numbers>
#include <random>
#include <stdexcept>
#include <utility>
#include <vector>

namespace softbench {
namespace {

using std::numbers::pi;

// ---------------------------------------------------------------------------------------------
// Tolerances

/// Taubin's transfer function (1 - lambda k)(1 - mu k) exceeds 1 by at most 0.03 k for small k;
/// a sphere of edge length h and radius R sits at k ~ h^2 / (2 R^2) ~ 0.002 (4 subdivisions of
/// an icosahedron), so 20 iterations change the radius by ~0.1% and the volume by ~0.4%.
constexpr double kTaubinVolumeDrift = 0.01;
/// Plain Laplacian steps scale the same sphere by (1 - lambda k) each: ~ -2% in radius, ~ -6%
/// in volume over 20 iterations. Demand at least this much to show the contrast is real.
constexpr double kLaplacianVolumeLoss = 0.03;
/// Affine combinations of points on a plane stay on it up to a few roundings per step.
constexpr double kPlanarity = 1e-12;

// ---------------------------------------------------------------------------------------------
// Test meshes

/// A unit-radius icosphere: an icosahedron whose triangles are split in four `subdivisions`
/// times, new vertices pushed onto the sphere. Outward oriented.
TriMesh icosphere(int subdivisions) {
  const double g = (1.0 + std::sqrt(5.0)) / 2.0;
  std::vector<Eigen::Vector3d> vertices = {{-1, g, 0}, {1, g, 0}, {-1, -g, 0}, {1, -g, 0},
                                           {0, -1, g}, {0, 1, g}, {0, -1, -g}, {0, 1, -g},
                                           {g, 0, -1}, {g, 0, 1}, {-g, 0, -1}, {-g, 0, 1}};
  std::vector<std::array<int, 3>> triangles = {
      {0, 11, 5},  {0, 5, 1},  {0, 1, 7},  {0, 7, 10}, {0, 10, 11}, {1, 5, 9}, {5, 11, 4},
      {11, 10, 2}, {10, 7, 6}, {7, 1, 8},  {3, 9, 4},  {3, 4, 2},   {3, 2, 6}, {3, 6, 8},
      {3, 8, 9},   {4, 9, 5},  {2, 4, 11}, {6, 2, 10}, {8, 6, 7},   {9, 8, 1}};
  for (auto& v : vertices) {
    v.normalize();
  }
  for (int level = 0; level < subdivisions; ++level) {
    std::map<std::pair<int, int>, int> midpoint_of;
    auto midpoint = [&](int a, int b) {
      const auto key = std::minmax(a, b);
      const auto [it, inserted] = midpoint_of.emplace(key, static_cast<int>(vertices.size()));
      if (inserted) {
        vertices.push_back((vertices[a] + vertices[b]).normalized());
      }
      return it->second;
    };
    std::vector<std::array<int, 3>> finer;
    for (const auto& [a, b, c] : triangles) {
      const int ab = midpoint(a, b);
      const int bc = midpoint(b, c);
      const int ca = midpoint(c, a);
      finer.insert(finer.end(), {{a, ab, ca}, {b, bc, ab}, {c, ca, bc}, {ab, bc, ca}});
    }
    triangles = std::move(finer);
  }
  TriMesh mesh;
  mesh.vertices.resize(3, static_cast<Eigen::Index>(vertices.size()));
  for (std::size_t v = 0; v < vertices.size(); ++v) {
    mesh.vertices.col(static_cast<Eigen::Index>(v)) = vertices[v];
  }
  mesh.triangles.resize(3, static_cast<Eigen::Index>(triangles.size()));
  for (std::size_t t = 0; t < triangles.size(); ++t) {
    mesh.triangles.col(static_cast<Eigen::Index>(t)) << triangles[t][0], triangles[t][1],
        triangles[t][2];
  }
  return mesh;
}

/// Each vertex moved along its radius by a uniform random fraction in [-amplitude, amplitude].
void add_radial_noise(TriMesh& mesh, double amplitude, unsigned seed) {
  std::mt19937 random(seed);
  std::uniform_real_distribution<double> noise(-amplitude, amplitude);
  for (int v = 0; v < mesh.num_vertices(); ++v) {
    mesh.vertices.col(v) *= 1.0 + noise(random);
  }
}

/// The mean angle (rad) between the normals of triangles sharing an edge: how faceted it looks.
double mean_crease_angle(const TriMesh& mesh) {
  std::map<std::pair<int, int>, std::vector<Eigen::Vector3d>> normals_at_edge;
  for (int t = 0; t < mesh.num_triangles(); ++t) {
    const auto c = mesh.triangles.col(t);
    const Eigen::Vector3d normal = (mesh.vertices.col(c(1)) - mesh.vertices.col(c(0)))
                                       .cross(mesh.vertices.col(c(2)) - mesh.vertices.col(c(0)))
                                       .normalized();
    for (int k = 0; k < 3; ++k) {
      normals_at_edge[std::minmax(c(k), c((k + 1) % 3))].push_back(normal);
    }
  }
  double sum = 0.0;
  int count = 0;
  for (const auto& [edge, normals] : normals_at_edge) {
    if (normals.size() == 2) {
      sum += std::acos(std::clamp(normals[0].dot(normals[1]), -1.0, 1.0));
      ++count;
    }
  }
  return sum / count;
}

double rms_radius_deviation(const TriMesh& mesh, double radius) {
  return std::sqrt((mesh.vertices.colwise().norm().array() - radius).square().mean());
}

/// An n x n grid of squares in the plane through `origin` spanned by u and v, each square split
/// into two triangles, inner vertices jittered within the plane.
TriMesh jittered_plane(int n,
                       const Eigen::Vector3d& origin,
                       const Eigen::Vector3d& u,
                       const Eigen::Vector3d& v,
                       unsigned seed) {
  std::mt19937 random(seed);
  std::uniform_real_distribution<double> jitter(-0.3, 0.3);
  TriMesh mesh;
  mesh.vertices.resize(3, (n + 1) * (n + 1));
  for (int j = 0; j <= n; ++j) {
    for (int i = 0; i <= n; ++i) {
      const bool inner = i > 0 && j > 0 && i < n && j < n;
      const double a = i + (inner ? jitter(random) : 0.0);
      const double b = j + (inner ? jitter(random) : 0.0);
      mesh.vertices.col(i + (n + 1) * j) = origin + a * u + b * v;
    }
  }
  mesh.triangles.resize(3, 2 * n * n);
  for (int j = 0; j < n; ++j) {
    for (int i = 0; i < n; ++i) {
      const int corner = i + (n + 1) * j;
      mesh.triangles.col(2 * (i + n * j)) << corner, corner + 1, corner + n + 2;
      mesh.triangles.col(2 * (i + n * j) + 1) << corner, corner + n + 2, corner + n + 1;
    }
  }
  return mesh;
}

// ---------------------------------------------------------------------------------------------
// Tests

TEST(TaubinSmoothing, OneIterationIsALambdaStepThenAMuStep) {
  // On a lone triangle each umbrella is 3/2 (centroid - x), so one step with factor f scales the
  // triangle about its centroid by 1 - 3f/2, and one iteration by (1 - 1.5 lambda)(1 - 1.5 mu).
  TriMesh triangle;
  triangle.vertices.resize(3, 3);
  triangle.vertices << 0.0, 2.0, 0.5,  //
      0.0, 0.0, 1.5,                   //
      1.0, 1.0, 1.0;
  triangle.triangles.resize(3, 1);
  triangle.triangles << 0, 1, 2;
  const Eigen::Vector3d centroid = triangle.vertices.rowwise().mean();
  const double lambda = 0.5;
  const double mu = -0.53;
  const Eigen::Matrix3Xd expected =
      (triangle.vertices.colwise() - centroid) * ((1.0 - 1.5 * lambda) * (1.0 - 1.5 * mu));
  taubin_smooth(triangle, 1, lambda, mu);
  EXPECT_TRUE((triangle.vertices.colwise() - centroid).isApprox(expected, test::kRoundoff))
      << triangle.vertices;
}

TEST(TaubinSmoothing, ReducesNoiseOnASphere) {
  TriMesh sphere = icosphere(4);
  add_radial_noise(sphere, 0.02, 11);
  const double noisy = rms_radius_deviation(sphere, 1.0);
  taubin_smooth(sphere, 10);
  const double smoothed = rms_radius_deviation(sphere, 1.0);
  testing::Test::RecordProperty("noisy_rms", std::to_string(noisy));
  testing::Test::RecordProperty("smoothed_rms", std::to_string(smoothed));
  EXPECT_LT(smoothed, 0.5 * noisy);
}

TEST(TaubinSmoothing, PreservesASpheresVolumeWherePlainLaplacianSmoothingShrinksIt) {
  const TriMesh original = icosphere(4);
  const double volume = enclosed_volume(original);

  TriMesh taubin = original;
  taubin_smooth(taubin, 20, 0.5, -0.53);
  const double taubin_change = std::abs(enclosed_volume(taubin) / volume - 1.0);

  TriMesh laplacian = original;
  taubin_smooth(laplacian, 20, 0.5, 0.0);  // mu = 0: the second step does nothing
  const double laplacian_loss = 1.0 - enclosed_volume(laplacian) / volume;

  testing::Test::RecordProperty("taubin_volume_change", std::to_string(taubin_change));
  testing::Test::RecordProperty("laplacian_volume_loss", std::to_string(laplacian_loss));
  EXPECT_LT(taubin_change, kTaubinVolumeDrift);
  EXPECT_GT(laplacian_loss, kLaplacianVolumeLoss);
  EXPECT_GT(laplacian_loss, 5.0 * taubin_change);
}

TEST(TaubinSmoothing, LeavesConnectivityUnchanged) {
  TriMesh sphere = icosphere(3);
  add_radial_noise(sphere, 0.05, 3);
  const Eigen::Matrix3Xi triangles = sphere.triangles;
  const int vertex_count = sphere.num_vertices();
  taubin_smooth(sphere, 5);
  EXPECT_EQ(sphere.triangles, triangles);
  EXPECT_EQ(sphere.num_vertices(), vertex_count);
  EXPECT_TRUE(sphere.vertices.allFinite());
}

TEST(TaubinSmoothing, KeepsAPlaneFlat) {
  const Eigen::Vector3d origin(0.3, -1.2, 2.0);
  const Eigen::Vector3d u = Eigen::Vector3d(1.0, 0.4, -0.2) * 0.1;
  const Eigen::Vector3d v = Eigen::Vector3d(-0.3, 0.5, 0.9) * 0.1;
  const Eigen::Vector3d normal = u.cross(v).normalized();
  TriMesh plane = jittered_plane(12, origin, u, v, 5);
  const Eigen::Matrix3Xd before = plane.vertices;
  taubin_smooth(plane, 10);
  EXPECT_GT((plane.vertices - before).norm(), 0.0) << "nothing was smoothed";
  for (int i = 0; i < plane.num_vertices(); ++i) {
    EXPECT_NEAR(normal.dot(plane.vertices.col(i) - origin), 0.0, kPlanarity) << "vertex " << i;
  }
}

TEST(TaubinSmoothing, VerticesWithoutNeighboursStayPut) {
  TriMesh sphere = icosphere(2);
  add_radial_noise(sphere, 0.05, 9);
  const Eigen::Vector3d lonely(5.0, -4.0, 3.0);
  sphere.vertices.conservativeResize(3, sphere.num_vertices() + 1);
  sphere.vertices.col(sphere.num_vertices() - 1) = lonely;
  taubin_smooth(sphere, 5);
  EXPECT_EQ(Eigen::Vector3d(sphere.vertices.col(sphere.num_vertices() - 1)), lonely);
}

TEST(TaubinSmoothing, ZeroIterationsChangeNothing) {
  TriMesh sphere = icosphere(2);
  add_radial_noise(sphere, 0.05, 1);
  const Eigen::Matrix3Xd before = sphere.vertices;
  taubin_smooth(sphere, 0);
  EXPECT_EQ(sphere.vertices, before);
}

TEST(TaubinSmoothing, RejectsTrianglesIndexingMissingVertices) {
  TriMesh broken = icosphere(1);
  broken.triangles(1, 3) = broken.num_vertices();
  EXPECT_THROW(taubin_smooth(broken, 1), std::invalid_argument);
}

// The thesis's pipeline: a segmented (inside / outside) volume, marching cubes, then Taubin
// smoothing of the staircase the binary samples leave (every vertex at an edge midpoint).
TEST(TaubinSmoothing, SmoothsTheStaircaseOfABinaryVolumeWithoutOpeningOrShrinkingIt) {
  const double radius = 1.0;
  const double h = radius / 12.0;
  ScalarGrid grid;
  grid.size = Eigen::Vector3i::Constant(static_cast<int>(std::ceil(2.0 * radius / h)) + 5);
  grid.spacing = Eigen::Vector3d::Constant(h);
  grid.origin = Eigen::Vector3d::Constant(-(grid.size.x() - 1) * h / 2.0)
                + Eigen::Vector3d(0.21, 0.37, 0.11) * h;
  grid.values.resize(static_cast<std::size_t>(grid.size.prod()));
  for (int k = 0; k < grid.size.z(); ++k) {
    for (int j = 0; j < grid.size.y(); ++j) {
      for (int i = 0; i < grid.size.x(); ++i) {
        grid.at(i, j, k) = grid.position(i, j, k).norm() < radius ? 1.0f : 0.0f;
      }
    }
  }
  TriMesh mesh = marching_cubes(grid, 0.5f);
  const double crease_before = mean_crease_angle(mesh);
  const double deviation_before = rms_radius_deviation(mesh, radius);

  taubin_smooth(mesh, 10);

  const SurfaceTopology topo = surface_topology(mesh.triangles, mesh.num_vertices());
  EXPECT_TRUE(topo.closed_manifold());
  EXPECT_TRUE(topo.oriented());
  const double exact_volume = 4.0 / 3.0 * pi * radius * radius * radius;
  EXPECT_NEAR(enclosed_volume(mesh), exact_volume, kTaubinVolumeDrift * exact_volume);
  const double crease_after = mean_crease_angle(mesh);
  const double deviation_after = rms_radius_deviation(mesh, radius);
  testing::Test::RecordProperty("mean_crease_before_rad", std::to_string(crease_before));
  testing::Test::RecordProperty("mean_crease_after_rad", std::to_string(crease_after));
  testing::Test::RecordProperty("rms_radius_deviation_before", std::to_string(deviation_before));
  testing::Test::RecordProperty("rms_radius_deviation_after", std::to_string(deviation_after));
  EXPECT_LT(crease_after, 0.5 * crease_before);
  EXPECT_LT(deviation_after, deviation_before);
}

}  // namespace
}  // namespace softbench
