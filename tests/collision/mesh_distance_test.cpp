// SPDX-License-Identifier: MIT
#include "collision/mesh_distance.h"

#include "collision/closest_point_triangle.h"
#include "tests/collision/bvh_test_meshes.h"

#include <Eigen/Core>
#include <gtest/gtest.h>

#include <cmath>
#include <cstdint>
#include <limits>
#include <optional>
#include <random>
#include <string>
#include <vector>

namespace softbench::collision {
namespace {

using test::box_surface;
using test::icosphere;
using test::perturb_radially;
using test::random_rotation;

// Distances here are O(1) sums of a few products: a few ulps each.
constexpr double kRoundoff = 1e-12;
// Points closer than this to the surface are not classified by the references below.
constexpr double kAmbiguous = 1e-9;

std::vector<BvhSchedule> distance_schedules() {
  return {BvhSchedule::instrument(), BvhSchedule::liver(), BvhSchedule::all_sphere(),
          BvhSchedule::all_aabb(), BvhSchedule::layered(1, 1, 30, 1)};
}

Eigen::Vector3d random_point(std::mt19937& rng, double scale) {
  std::uniform_real_distribution<double> unit(-1.0, 1.0);
  return scale * Eigen::Vector3d(unit(rng), unit(rng), unit(rng));
}

TEST(ClosestPointOnTriangle, IsInTheTriangleAndNoSampledPointIsCloser) {
  std::mt19937 rng(21);
  constexpr int kSamples = 40;
  for (int trial = 0; trial < 500; ++trial) {
    const Eigen::Vector3d a = random_point(rng, 1), b = random_point(rng, 1),
                          c = random_point(rng, 1), p = random_point(rng, 2);
    const TrianglePoint closest = closest_point_on_triangle(p, a, b, c);
    const Eigen::Vector3d& w = closest.barycentric;
    EXPECT_GE(w.minCoeff(), 0.0);
    EXPECT_NEAR(w.sum(), 1.0, kRoundoff);
    EXPECT_LT((w(0) * a + w(1) * b + w(2) * c - closest.point).norm(), kRoundoff);
    const double distance = (p - closest.point).norm();
    for (int i = 0; i <= kSamples; ++i) {
      for (int j = 0; i + j <= kSamples; ++j) {
        const Eigen::Vector3d s = a + (b - a) * i / kSamples + (c - a) * j / kSamples;
        ASSERT_GE((p - s).norm(), distance - kRoundoff) << "trial " << trial;
      }
    }
    // The offset is normal to the feature: to the plane on a face, to the edge on an edge.
    const Eigen::Vector3d offset = p - closest.point;
    switch (closest.feature) {
      case TriangleFeature::kFace:
        EXPECT_LT(offset.cross((b - a).cross(c - a)).norm(), 1e-9);
        break;
      case TriangleFeature::kEdge01:
        EXPECT_NEAR(offset.dot(b - a), 0.0, 1e-9);
        break;
      case TriangleFeature::kEdge12:
        EXPECT_NEAR(offset.dot(c - b), 0.0, 1e-9);
        break;
      case TriangleFeature::kEdge20:
        EXPECT_NEAR(offset.dot(a - c), 0.0, 1e-9);
        break;
      default:
        EXPECT_EQ(w.maxCoeff(), 1.0);
    }
  }
}

TEST(ClosestPointOnTriangle, HandlesDegenerateTriangles) {
  const Eigen::Vector3d a(0, 0, 0), b(1, 0, 0), c(2, 0, 0);  // collinear
  const TrianglePoint on_line = closest_point_on_triangle(Eigen::Vector3d(1.5, 1, 0), a, b, c);
  EXPECT_LT((on_line.point - Eigen::Vector3d(1.5, 0, 0)).norm(), kRoundoff);
  const TrianglePoint beyond = closest_point_on_triangle(Eigen::Vector3d(3, 1, 0), a, b, c);
  EXPECT_EQ(beyond.point, c);
  const TrianglePoint point = closest_point_on_triangle(Eigen::Vector3d(0, 2, 0), b, b, b);
  EXPECT_EQ(point.point, b);
  EXPECT_TRUE(point.point.allFinite());
  const TrianglePoint repeated = closest_point_on_triangle(Eigen::Vector3d(0.5, -1, 0), a, a, b);
  EXPECT_LT((repeated.point - Eigen::Vector3d(0.5, 0, 0)).norm(), kRoundoff);
}

double brute_force_distance(const TriMesh& mesh,
                            const Eigen::Matrix3Xd& positions,
                            const Eigen::Vector3d& p) {
  double best = std::numeric_limits<double>::infinity();
  for (int t = 0; t < mesh.num_triangles(); ++t) {
    const auto tri = mesh.triangles.col(t);
    const TrianglePoint q = closest_point_on_triangle(p, positions.col(tri(0)),
                                                      positions.col(tri(1)), positions.col(tri(2)));
    best = std::min(best, (q.point - p).norm());
  }
  return best;
}

// Inside a mesh that is star-shaped about the origin (the icospheres, perturbed radially, and the
// centred box): the ray from the origin through p leaves the mesh once, at distance `exit`;
// p is inside iff |p| < exit. Returns 0 (unknown) within kAmbiguous of the surface.
int star_shaped_side(const TriMesh& mesh,
                     const Eigen::Matrix3Xd& positions,
                     const Eigen::Vector3d& p) {
  const Eigen::Vector3d direction = p.normalized();
  double exit = std::numeric_limits<double>::infinity();
  for (int t = 0; t < mesh.num_triangles(); ++t) {
    // Moeller-Trumbore ray-triangle intersection, barycentrics allowed a hair outside so that
    // rays through edges and vertices still hit.
    const Eigen::Vector3d v0 = positions.col(mesh.triangles(0, t));
    const Eigen::Vector3d e1 = positions.col(mesh.triangles(1, t)) - v0;
    const Eigen::Vector3d e2 = positions.col(mesh.triangles(2, t)) - v0;
    const Eigen::Vector3d h = direction.cross(e2);
    const double det = e1.dot(h);
    if (std::abs(det) < 1e-15) {
      continue;
    }
    const Eigen::Vector3d s = -v0;
    const double u = s.dot(h) / det;
    const Eigen::Vector3d q = s.cross(e1);
    const double v = direction.dot(q) / det;
    if (u < -1e-12 || v < -1e-12 || u + v > 1 + 1e-12) {
      continue;
    }
    const double distance = e2.dot(q) / det;
    if (distance > 0) {
      exit = std::min(exit, distance);
    }
  }
  if (std::abs(p.norm() - exit) < kAmbiguous) {
    return 0;
  }
  return p.norm() < exit ? -1 : 1;
}

// Query points: random ones at several scales, and ones just off every vertex and edge midpoint
// (where the face normals alone give the wrong sign) in random directions.
std::vector<Eigen::Vector3d> query_points(const TriMesh& mesh,
                                          const Eigen::Matrix3Xd& positions,
                                          std::mt19937& rng) {
  std::vector<Eigen::Vector3d> points;
  for (int i = 0; i < 300; ++i) {
    points.push_back(random_point(rng, i % 3 == 0 ? 3.0 : 1.2));
  }
  std::normal_distribution<double> normal;
  std::uniform_real_distribution<double> log_offset(-6.0, -1.5);
  auto near = [&](const Eigen::Vector3d& anchor) {
    const Eigen::Vector3d direction(normal(rng), normal(rng), normal(rng));
    points.push_back(anchor + std::pow(10.0, log_offset(rng)) * direction.normalized());
  };
  for (Eigen::Index v = 0; v < positions.cols(); ++v) {
    near(positions.col(v));
  }
  for (int t = 0; t < mesh.num_triangles(); ++t) {
    for (int k = 0; k < 3; ++k) {
      near(0.5
           * (positions.col(mesh.triangles(k, t)) + positions.col(mesh.triangles((k + 1) % 3, t))));
    }
  }
  return points;
}

struct NamedMesh {
  std::string name;
  TriMesh mesh;
};

std::vector<NamedMesh> closed_meshes() {
  std::mt19937 rng(22);
  TriMesh lumpy = icosphere(2, 1.0);
  perturb_radially(lumpy, 0.25, rng);  // non-convex, still star-shaped about the origin
  TriMesh box = box_surface(3, Eigen::Vector3d(1.0, 0.6, 1.4));
  box.vertices.colwise() -= Eigen::Vector3d(0.5, 0.3, 0.7);  // centred: star-shaped about 0
  return {{"icosphere", icosphere(2, 1.0)}, {"lumpy", lumpy}, {"box", box}};
}

void expect_matches_references(const MeshDistance& distance,
                               const TriMesh& mesh,
                               const Eigen::Matrix3Xd& positions,
                               std::mt19937& rng,
                               const std::string& label) {
  SCOPED_TRACE(label);
  int inside = 0, outside = 0;
  for (const Eigen::Vector3d& p : query_points(mesh, positions, rng)) {
    QueryStats stats;
    const MeshDistance::Nearest nearest = distance.nearest(p, &stats);
    ASSERT_GE(nearest.triangle, 0);
    const double expected = brute_force_distance(mesh, positions, p);
    ASSERT_NEAR(nearest.distance, expected, kRoundoff) << p.transpose();
    EXPECT_NEAR((nearest.point - p).norm(), nearest.distance, kRoundoff);
    EXPECT_NEAR(std::abs(nearest.signed_distance), nearest.distance, 0.0);
    EXPECT_NEAR(nearest.normal.norm(), 1.0, kRoundoff);
    // The closest point lies on the triangle it names, with the weights it names.
    const auto tri = mesh.triangles.col(nearest.triangle);
    const Eigen::Vector3d from_weights = nearest.barycentric(0) * positions.col(tri(0))
                                         + nearest.barycentric(1) * positions.col(tri(1))
                                         + nearest.barycentric(2) * positions.col(tri(2));
    EXPECT_LT((from_weights - nearest.point).norm(), kRoundoff);
    const int side = star_shaped_side(mesh, positions, p);
    if (side != 0) {
      EXPECT_EQ(nearest.signed_distance < 0.0, side < 0) << p.transpose();
      (side < 0 ? inside : outside) += 1;
    }
    EXPECT_LE(stats.tri_tests, mesh.num_triangles());
  }
  EXPECT_GT(inside, 100);
  EXPECT_GT(outside, 100);
}

TEST(MeshDistance, NearestEqualsBruteForceAndInsideIsRightNearVerticesAndEdges) {
  std::mt19937 rng(23);
  for (const NamedMesh& named : closed_meshes()) {
    for (const BvhSchedule& schedule : distance_schedules()) {
      const MeshDistance distance(named.mesh.vertices, named.mesh.triangles, schedule);
      expect_matches_references(distance, named.mesh, named.mesh.vertices, rng, named.name);
    }
  }
}

// Bounded by a radius, the query gives the nearest point when it is nearer than the radius and
// nothing otherwise, and a point far from the surface costs a few node tests.
TEST(MeshDistance, NearestWithinARadiusIsTheNearestPointOrNothing) {
  std::mt19937 rng(25);
  for (const NamedMesh& named : closed_meshes()) {
    SCOPED_TRACE(named.name);
    const MeshDistance distance(named.mesh.vertices, named.mesh.triangles);
    int found = 0, missed = 0;
    for (const Eigen::Vector3d& p : query_points(named.mesh, named.mesh.vertices, rng)) {
      const MeshDistance::Nearest nearest = distance.nearest(p);
      for (const double radius : {1e-4, 1e-2, 0.1}) {
        const std::optional<MeshDistance::Nearest> within = distance.nearest_within(p, radius);
        if (nearest.distance < radius) {
          ASSERT_TRUE(within.has_value()) << p.transpose() << " radius " << radius;
          EXPECT_EQ(within->distance, nearest.distance);
          EXPECT_EQ(within->signed_distance, nearest.signed_distance);
          EXPECT_EQ(within->triangle, nearest.triangle);
          ++found;
        } else {
          EXPECT_FALSE(within.has_value()) << p.transpose() << " radius " << radius;
          ++missed;
        }
      }
    }
    EXPECT_GT(found, 100);
    EXPECT_GT(missed, 100);
    // 3 units from the centre of a surface of radius ~1: nothing within 0.1, found in a few
    // node tests (the root's box is 2 units away), where the unbounded query searches.
    QueryStats bounded, unbounded;
    const Eigen::Vector3d far(3.0, 0.1, 0.2);
    EXPECT_FALSE(distance.nearest_within(far, 0.1, &bounded).has_value());
    distance.nearest(far, &unbounded);
    EXPECT_EQ(bounded.tri_tests, 0);
    EXPECT_GT(unbounded.tri_tests, 0);
  }
}

// A hint (the triangle an earlier query found) changes what a query costs, never what it finds:
// the same distance and side from a right, a stale or a wrong hint.
TEST(MeshDistance, AHintChangesTheCostOfAQueryNotItsAnswer) {
  std::mt19937 rng(26);
  std::uniform_int_distribution<int> any_axis(0, 2);
  for (const NamedMesh& named : closed_meshes()) {
    SCOPED_TRACE(named.name);
    const MeshDistance distance(named.mesh.vertices, named.mesh.triangles);
    std::uniform_int_distribution<int> any_triangle(0, named.mesh.num_triangles() - 1);
    for (const Eigen::Vector3d& p : query_points(named.mesh, named.mesh.vertices, rng)) {
      const MeshDistance::Nearest earlier = distance.nearest(p);
      Eigen::Vector3d moved = p;
      moved(any_axis(rng)) += 1e-3;
      constexpr double kRadius = 0.3;
      const std::optional<MeshDistance::Nearest> plain = distance.nearest_within(moved, kRadius);
      for (const int hint : {earlier.triangle, any_triangle(rng)}) {
        const std::optional<MeshDistance::Nearest> hinted =
            distance.nearest_within(moved, kRadius, nullptr, hint);
        ASSERT_EQ(hinted.has_value(), plain.has_value()) << moved.transpose();
        if (plain) {
          EXPECT_NEAR(hinted->distance, plain->distance, kRoundoff) << moved.transpose();
          EXPECT_NEAR(hinted->signed_distance, plain->signed_distance, kRoundoff);
          EXPECT_LT((hinted->point - plain->point).norm(), kRoundoff);
        }
      }
      const MeshDistance::Nearest unbounded = distance.nearest(moved, nullptr, any_triangle(rng));
      EXPECT_NEAR(unbounded.signed_distance, distance.nearest(moved).signed_distance, kRoundoff);
    }
  }
}

// What the hint is for: a point some way off a finely meshed surface, searched within a radius
// larger than its distance (the contact's instrument points a few millimetres inside or outside
// the tissue, searched within the fold depth), and moved a little since the query that found its
// hint. Started from the hint's distance, the descent opens only the nodes nearer than that,
// where from the radius it opens those nearer than the best point found so far, which the
// nearer-child-first order finds only as it goes.
TEST(MeshDistance, AHintFromANearbyQueryOpensFewerNodes) {
  std::mt19937 rng(27);
  TriMesh sphere = icosphere(4, 1.0);
  perturb_radially(sphere, 0.25, rng);
  const MeshDistance distance(sphere.vertices, sphere.triangles, BvhSchedule::liver());
  std::normal_distribution<double> normal;
  std::uniform_real_distribution<double> offset(-0.2, 0.2);
  std::int64_t hinted_tests = 0, plain_tests = 0;
  for (int i = 0; i < 500; ++i) {
    const Eigen::Vector3d direction =
        Eigen::Vector3d(normal(rng), normal(rng), normal(rng)).normalized();
    const Eigen::Vector3d p = (1.0 + offset(rng)) * direction;
    const int hint = distance.nearest(p).triangle;
    const Eigen::Vector3d moved = p + 0.01 * Eigen::Vector3d(normal(rng), normal(rng), normal(rng));
    QueryStats plain, hinted;
    const std::optional<MeshDistance::Nearest> without =
        distance.nearest_within(moved, 0.5, &plain);
    const std::optional<MeshDistance::Nearest> with =
        distance.nearest_within(moved, 0.5, &hinted, hint);
    ASSERT_TRUE(without && with);
    EXPECT_NEAR(with->distance, without->distance, kRoundoff);
    hinted_tests += hinted.node_visits + hinted.tri_tests;
    plain_tests += plain.node_visits + plain.tri_tests;
  }
  // 0.85 here; on the liver pressed into by the probe, 0.55 (the tissue's samples lie deeper).
  EXPECT_LT(static_cast<double>(hinted_tests), 0.9 * static_cast<double>(plain_tests))
      << hinted_tests << " node and triangle tests with hints, " << plain_tests << " without";
}

TEST(MeshDistance, UpdateFollowsMovedVertices) {
  std::mt19937 rng(24);
  for (const NamedMesh& named : closed_meshes()) {
    MeshDistance distance(named.mesh.vertices, named.mesh.triangles);
    // Scaled and rotated about the origin (stays star-shaped about it), then squashed.
    Eigen::Matrix3Xd positions = 0.7 * random_rotation(rng) * named.mesh.vertices;
    positions.row(2) *= 0.5;
    distance.update(positions);
    expect_matches_references(distance, named.mesh, positions, rng, named.name + " moved");
  }
}

TEST(MeshDistance, CornersAndEdgesOfABoxGetTheRightSide) {
  const TriMesh box = box_surface(1);  // the unit cube, two triangles per face
  const MeshDistance distance(box.vertices, box.triangles);
  for (const double offset : {1e-3, 1e-7}) {
    // Just outside a corner and an edge: the closest features are a vertex and an edge whose
    // faces' normals disagree in sign there.
    EXPECT_GT(distance.signed_distance(Eigen::Vector3d(1 + offset, 1 + offset, 1 + offset)), 0);
    EXPECT_GT(distance.signed_distance(Eigen::Vector3d(-offset, 0.5, 1 + offset)), 0);
    EXPECT_GT(distance.signed_distance(Eigen::Vector3d(0.5, 1 + offset, 1 + 0.5 * offset)), 0);
    EXPECT_LT(distance.signed_distance(Eigen::Vector3d(1 - offset, 1 - offset, 1 - offset)), 0);
    EXPECT_LT(distance.signed_distance(Eigen::Vector3d(offset, 0.5, 1 - offset)), 0);
    EXPECT_NEAR(distance.signed_distance(Eigen::Vector3d(1 + offset, 1 + offset, 1 + offset)),
                std::sqrt(3.0) * offset, 1e-15);
  }
  // On the surface: distance 0, not inside.
  EXPECT_EQ(distance.signed_distance(Eigen::Vector3d(0.5, 0.5, 1.0)), 0.0);
  EXPECT_FALSE(distance.inside(Eigen::Vector3d(1.0, 1.0, 1.0)));
  EXPECT_TRUE(distance.inside(Eigen::Vector3d(0.5, 0.5, 0.5)));
  EXPECT_EQ(distance.bounds().min, Eigen::Vector3d::Zero());
  EXPECT_EQ(distance.bounds().max, Eigen::Vector3d::Ones());
}

TEST(MeshDistance, EmptyMeshHasNoNearestPoint) {
  const MeshDistance distance(Eigen::Matrix3Xd(3, 0), Eigen::Matrix3Xi(3, 0));
  const MeshDistance::Nearest nearest = distance.nearest(Eigen::Vector3d::Zero());
  EXPECT_EQ(nearest.triangle, -1);
  EXPECT_FALSE(distance.inside(Eigen::Vector3d::Zero()));
  EXPECT_TRUE(distance.bounds().empty());
}

}  // namespace
}  // namespace softbench::collision
