// SPDX-License-Identifier: MIT
#include "collision/bvh.h"

#include "collision/bvh_collide.h"
#include "collision/bvh_schedule.h"
#include "collision/tri_tri_projection.h"
#include "geometry/input_error.h"
#include "tests/collision/bvh_test_meshes.h"

#include <Eigen/Core>
#include <gtest/gtest.h>

#include <algorithm>
#include <iterator>
#include <random>
#include <string>
#include <tuple>
#include <vector>

namespace softbench::collision {
namespace {

using test::box_surface;
using test::icosphere;
using test::jitter;
using test::perturb_radially;
using test::random_rotation;

struct NamedSchedule {
  std::string name;
  BvhSchedule schedule;
};

// The thesis's two trees, the two peers, a short mixed schedule and one whose depth limit is
// reached before the leaves get small (oversize leaves).
std::vector<NamedSchedule> schedules() {
  return {{"liver", BvhSchedule::liver()},
          {"instrument", BvhSchedule::instrument()},
          {"all_sphere", BvhSchedule::all_sphere()},
          {"all_aabb", BvhSchedule::all_aabb()},
          {"mixed_leaf3", BvhSchedule::layered(1, 2, 20, 3)},
          {"depth_limited", BvhSchedule::layered(1, 1, 1, 2)},
          // Sphere-only levels (no tie-breaker) above box-tested sphere levels: the parents'
          // radii are bounded through children whose spheres are the boxes' circumspheres.
          {"spheres_over_hybrid",
           BvhSchedule{{VolumeKind::kSphere, VolumeKind::kSphere, VolumeKind::kSphereAabb,
                        VolumeKind::kSphereAabb, VolumeKind::kAabb, VolumeKind::kAabb,
                        VolumeKind::kAabb, VolumeKind::kAabb},
                       4,
                       /*box_tie_breaker=*/false}}};
}

// A test-only narrow phase independent of collision/tri_tri_*: the separating-axis test over the
// two normals and the nine edge-edge directions, closed (touching intersects), plus the exact
// box test so that near-touching round-off cannot disagree with the tree's exact box filter. Any
// deterministic test that implies the triangles' convex hulls meet is a fair referee for the
// tree: the tree must find every pair it accepts.
struct SeparatingAxisTest {
  TriTriResult operator()(const Eigen::Vector3d& p0,
                          const Eigen::Vector3d& p1,
                          const Eigen::Vector3d& p2,
                          const Eigen::Vector3d& q0,
                          const Eigen::Vector3d& q1,
                          const Eigen::Vector3d& q2) const {
    TriTriResult result;
    Aabb box_p, box_q;
    box_p.extend(p0), box_p.extend(p1), box_p.extend(p2);
    box_q.extend(q0), box_q.extend(q1), box_q.extend(q2);
    if (!overlap(box_p, box_q)) {
      return result;
    }
    const Eigen::Vector3d p[3] = {p0, p1, p2}, q[3] = {q0, q1, q2};
    auto separates = [&](const Eigen::Vector3d& axis) {
      double p_min = p[0].dot(axis), p_max = p_min, q_min = q[0].dot(axis), q_max = q_min;
      for (int k = 1; k < 3; ++k) {
        p_min = std::min(p_min, p[k].dot(axis));
        p_max = std::max(p_max, p[k].dot(axis));
        q_min = std::min(q_min, q[k].dot(axis));
        q_max = std::max(q_max, q[k].dot(axis));
      }
      return p_max < q_min || q_max < p_min;
    };
    if (separates((p1 - p0).cross(p2 - p0)) || separates((q1 - q0).cross(q2 - q0))) {
      return result;
    }
    for (int i = 0; i < 3; ++i) {
      for (int j = 0; j < 3; ++j) {
        if (separates((p[(i + 1) % 3] - p[i]).cross(q[(j + 1) % 3] - q[j]))) {
          return result;
        }
      }
    }
    result.contact = TriTriContact::kSegment;
    result.a = box_p.center();
    result.b = box_q.center();
    return result;
  }
};

// Every (a, b) for which `test` says intersect, over all #T_a x #T_b pairs, sorted.
template <class Test>
std::vector<std::pair<int, int>> brute_force_pairs(const TriMesh& mesh_a,
                                                   const Eigen::Matrix3Xd& positions_a,
                                                   const TriMesh& mesh_b,
                                                   const Eigen::Matrix3Xd& positions_b,
                                                   const Test& test) {
  std::vector<std::pair<int, int>> pairs;
  for (int a = 0; a < mesh_a.num_triangles(); ++a) {
    const auto ta = mesh_a.triangles.col(a);
    for (int b = 0; b < mesh_b.num_triangles(); ++b) {
      const auto tb = mesh_b.triangles.col(b);
      if (test(positions_a.col(ta(0)), positions_a.col(ta(1)), positions_a.col(ta(2)),
               positions_b.col(tb(0)), positions_b.col(tb(1)), positions_b.col(tb(2)))
              .intersect()) {
        pairs.emplace_back(a, b);
      }
    }
  }
  return pairs;
}

std::vector<std::pair<int, int>> sorted_indices(const std::vector<TrianglePair>& pairs) {
  std::vector<std::pair<int, int>> indices;
  for (const TrianglePair& pair : pairs) {
    indices.emplace_back(pair.a, pair.b);
  }
  std::sort(indices.begin(), indices.end());
  return indices;
}

// Checks every structural invariant of a built tree and that each node's volumes hold its
// triangles at `positions`.
void expect_valid_tree(const Bvh& tree,
                       const TriMesh& mesh,
                       const Eigen::Matrix3Xd& positions,
                       const std::string& label) {
  SCOPED_TRACE(label);
  const BvhSchedule& schedule = tree.schedule();
  const std::vector<BvhNode>& nodes = tree.nodes();
  ASSERT_FALSE(nodes.empty());
  std::vector<int> times_seen(static_cast<std::size_t>(mesh.num_triangles()), 0);
  int leaves = 0, oversize = 0, min_leaf_level = 1000, max_leaf_level = 0;
  // Subtree triangle lists, bottom-up (children come after parents).
  std::vector<std::vector<int>> subtree(nodes.size());
  for (std::size_t i = nodes.size(); i-- > 0;) {
    const BvhNode& node = nodes[i];
    EXPECT_EQ(node.kind, schedule.kind_at(node.level));
    EXPECT_LT(node.level, schedule.max_levels());
    if (node.is_leaf()) {
      ++leaves;
      min_leaf_level = std::min(min_leaf_level, static_cast<int>(node.level));
      max_leaf_level = std::max(max_leaf_level, static_cast<int>(node.level));
      if (node.count > schedule.max_leaf_triangles) {
        ++oversize;
        // Only the depth limit may leave a leaf larger than the schedule allows.
        EXPECT_EQ(node.level, schedule.max_levels() - 1);
      }
      for (const int t : tree.leaf_triangles(node)) {
        ++times_seen[static_cast<std::size_t>(t)];
        subtree[i].push_back(t);
      }
      std::vector<int> expected_vertices;
      for (const int t : subtree[i]) {
        for (int k = 0; k < 3; ++k) {
          expected_vertices.push_back(mesh.triangles(k, t));
        }
      }
      std::sort(expected_vertices.begin(), expected_vertices.end());
      expected_vertices.erase(std::unique(expected_vertices.begin(), expected_vertices.end()),
                              expected_vertices.end());
      const auto vertices = tree.leaf_vertices(node);
      EXPECT_EQ(std::vector<int>(vertices.begin(), vertices.end()), expected_vertices);
    } else {
      ASSERT_GT(node.first, static_cast<int>(i));
      for (int child = node.first; child <= node.first + 1; ++child) {
        EXPECT_EQ(nodes[static_cast<std::size_t>(child)].level, node.level + 1);
        const auto& part = subtree[static_cast<std::size_t>(child)];
        subtree[i].insert(subtree[i].end(), part.begin(), part.end());
      }
    }
    Aabb exact;
    for (const int t : subtree[i]) {
      for (int k = 0; k < 3; ++k) {
        const Eigen::Vector3d p = positions.col(mesh.triangles(k, t));
        exact.extend(p);
        if (node.has_sphere()) {
          ASSERT_TRUE(node.sphere_of().contains(p)) << "node " << i << " triangle " << t;
        }
      }
    }
    // Boxes are tight (exact min/max), not merely containing.
    EXPECT_EQ(node.box.min, exact.min) << "node " << i;
    EXPECT_EQ(node.box.max, exact.max) << "node " << i;
    if (node.has_sphere()) {
      // The sphere is never larger than the box's circumsphere, up to its padding.
      const Sphere sphere = node.sphere_of();
      EXPECT_LE(sphere.radius, 0.5 * exact.extent().norm()
                                   + 1e-12 * (sphere.radius + sphere.center.cwiseAbs().maxCoeff()));
    }
  }
  for (int t = 0; t < mesh.num_triangles(); ++t) {
    EXPECT_EQ(times_seen[static_cast<std::size_t>(t)], 1) << "triangle " << t;
  }
  EXPECT_EQ(tree.info().leaves, leaves);
  EXPECT_EQ(tree.info().oversize_leaves, oversize);
  EXPECT_EQ(tree.info().levels, max_leaf_level + 1);
  EXPECT_LE(tree.info().levels, schedule.max_levels());
  // The median split keeps the tree balanced: all leaves on one level or two adjacent ones.
  EXPECT_LE(max_leaf_level - min_leaf_level, 1);
  // Depth: the first level at which ceil(#T / 2^d) fits in a leaf, or the limit.
  int depth = 0;
  while ((mesh.num_triangles() + (1 << depth) - 1) / (1 << depth) > schedule.max_leaf_triangles
         && depth + 1 < schedule.max_levels()) {
    ++depth;
  }
  EXPECT_EQ(tree.info().levels, depth + 1);
}

std::vector<TriMesh> test_meshes() {
  std::mt19937 rng(11);
  TriMesh lumpy = icosphere(3, 1.0);
  perturb_radially(lumpy, 0.2, rng);
  TriMesh box = box_surface(5, Eigen::Vector3d(0.7, 0.4, 1.1));
  return {icosphere(2), lumpy, box};
}

TEST(BvhBuild, InvariantsHoldForEveryScheduleAndMesh) {
  for (const TriMesh& mesh : test_meshes()) {
    for (const NamedSchedule& named : schedules()) {
      const Bvh tree(mesh.vertices, mesh.triangles, named.schedule);
      expect_valid_tree(tree, mesh, mesh.vertices,
                        named.name + " over " + std::to_string(mesh.num_triangles()));
    }
  }
}

TEST(BvhBuild, TheThesisLiverScheduleGivesElevenLevelsOverTheThesisTriangleCount) {
  // 9313 triangles (the thesis's liver) in leaves of <= 10: ceil(9313 / 2^10) = 10, so the tree
  // reaches exactly the 11 levels the thesis states, with no oversize leaf.
  TriMesh mesh = icosphere(5);  // 20480 triangles; keep the first 9313
  mesh.triangles.conservativeResize(3, 9313);
  const Bvh tree(mesh.vertices, mesh.triangles, BvhSchedule::liver());
  EXPECT_EQ(tree.info().levels, 11);
  EXPECT_EQ(tree.info().oversize_leaves, 0);
  EXPECT_LE(tree.info().max_leaf_triangles, 10);
}

TEST(BvhBuild, DepthLimitKeepsEveryTriangleInOversizeLeaves) {
  const TriMesh mesh = icosphere(2);  // 320 triangles, 3 levels -> 4 leaves of 80
  const Bvh tree(mesh.vertices, mesh.triangles, BvhSchedule::layered(1, 1, 1, 2));
  EXPECT_EQ(tree.info().levels, 3);
  EXPECT_EQ(tree.info().leaves, 4);
  EXPECT_EQ(tree.info().oversize_leaves, 4);
  EXPECT_EQ(tree.info().max_leaf_triangles, 80);
}

TEST(BvhBuild, RejectsBadInput) {
  const TriMesh mesh = icosphere(0);
  EXPECT_THROW(Bvh(mesh.vertices, mesh.triangles, BvhSchedule{{}, 10}), InputError);
  EXPECT_THROW(Bvh(mesh.vertices, mesh.triangles, BvhSchedule::all_aabb(61)), InputError);
  EXPECT_THROW(Bvh(mesh.vertices, mesh.triangles, BvhSchedule::all_aabb(5, 0)), InputError);
  Eigen::Matrix3Xi bad = mesh.triangles;
  bad(1, 3) = 12;
  EXPECT_THROW(Bvh(mesh.vertices, bad, BvhSchedule::liver()), InputError);
  Eigen::Matrix3Xd nan = mesh.vertices;
  nan(2, 5) = std::numeric_limits<double>::quiet_NaN();
  EXPECT_THROW(Bvh(nan, mesh.triangles, BvhSchedule::liver()), InputError);
  Bvh tree(mesh.vertices, mesh.triangles, BvhSchedule::liver());
  EXPECT_THROW(tree.refit(Eigen::Matrix3Xd::Zero(3, 11)), InputError);
}

TEST(BvhRefit, KeepsContainmentAndTightBoxesAfterRandomDeformations) {
  std::mt19937 rng(12);
  for (const TriMesh& mesh : test_meshes()) {
    for (const NamedSchedule& named : schedules()) {
      Bvh tree(mesh.vertices, mesh.triangles, named.schedule);
      const std::vector<BvhNode> before = tree.nodes();
      Eigen::Matrix3Xd positions = mesh.vertices;
      for (int step = 0; step < 4; ++step) {
        // Small jitter, then a large one that scrambles the geometry the split was made for,
        // then a rigid motion far from the origin.
        if (step < 2) {
          positions = jitter(positions, step == 0 ? 0.01 : 0.5, rng);
        } else {
          positions = (random_rotation(rng) * positions).colwise() + Eigen::Vector3d(50, -20, 3);
        }
        tree.refit(positions);
        expect_valid_tree(tree, mesh, positions, named.name + " step " + std::to_string(step));
      }
      // Refit keeps the topology.
      ASSERT_EQ(tree.nodes().size(), before.size());
      for (std::size_t i = 0; i < before.size(); ++i) {
        EXPECT_EQ(tree.nodes()[i].first, before[i].first);
        EXPECT_EQ(tree.nodes()[i].count, before[i].count);
      }
    }
  }
}

struct Placement {
  Eigen::Matrix3d rotation;
  Eigen::Vector3d translation;
};

// B placed about A's surface at many distances: inside A (no pair), straddling its surface
// (deep and shallow overlap) and outside (none).
std::vector<Placement> placements(std::mt19937& rng) {
  std::vector<Placement> result;
  std::normal_distribution<double> normal;
  for (const double distance : {0.0, 0.4, 0.7, 0.85, 1.0, 1.15, 1.3, 1.6, 2.5}) {
    for (int repeat = 0; repeat < 2; ++repeat) {
      const Eigen::Vector3d direction =
          Eigen::Vector3d(normal(rng), normal(rng), normal(rng)).normalized();
      result.push_back({random_rotation(rng), distance * direction});
    }
  }
  return result;
}

// Runs every schedule pair over B placed about A and checks the query against brute force with
// the same narrow-phase `test`; the pairs (and their results) must also be the same for every
// schedule pair. Returns the number of placements with and without pairs.
template <class Test>
std::pair<int, int> expect_brute_force_pairs(const Test& test, unsigned seed) {
  std::mt19937 rng(seed);
  TriMesh mesh_a = icosphere(3, 1.0);
  perturb_radially(mesh_a, 0.15, rng);
  std::vector<TriMesh> others = {icosphere(2, 0.45),
                                 box_surface(4, Eigen::Vector3d(0.5, 0.3, 0.6))};
  perturb_radially(others[0], 0.2, rng);
  CollideBuffers buffers;
  std::vector<TrianglePair> pairs;
  int with_pairs = 0, without = 0;
  for (const TriMesh& mesh_b : others) {
    for (const Placement& placement : placements(rng)) {
      const Eigen::Matrix3Xd positions_b =
          (placement.rotation * mesh_b.vertices).colwise() + placement.translation;
      const auto expected = brute_force_pairs(mesh_a, mesh_a.vertices, mesh_b, positions_b, test);
      (expected.empty() ? without : with_pairs) += 1;
      std::vector<TrianglePair> reference;
      for (const NamedSchedule& schedule_a : schedules()) {
        const Bvh tree_a(mesh_a.vertices, mesh_a.triangles, schedule_a.schedule);
        for (const NamedSchedule& schedule_b : schedules()) {
          // B's tree is built at its rest pose and refitted to the placement, as the instrument
          // is in a simulation.
          Bvh tree_b(mesh_b.vertices, mesh_b.triangles, schedule_b.schedule);
          tree_b.refit(positions_b);
          QueryStats stats;
          collide(tree_a, mesh_a.vertices, tree_b, positions_b, buffers, pairs, &stats, test);
          const auto found = sorted_indices(pairs);
          std::vector<std::pair<int, int>> missing, extra;
          std::set_difference(expected.begin(), expected.end(), found.begin(), found.end(),
                              std::back_inserter(missing));
          std::set_difference(found.begin(), found.end(), expected.begin(), expected.end(),
                              std::back_inserter(extra));
          EXPECT_TRUE(missing.empty() && extra.empty())
              << schedule_a.name << " vs " << schedule_b.name << ": " << missing.size()
              << " missing, " << extra.size() << " extra";
          EXPECT_EQ(stats.pairs_found, static_cast<std::int64_t>(pairs.size()));
          EXPECT_GE(stats.tri_tests, stats.pairs_found);
          EXPECT_LE(stats.tri_tests,
                    static_cast<std::int64_t>(mesh_a.num_triangles()) * mesh_b.num_triangles());
          // Same pairs with the same results whatever the schedules.
          std::sort(pairs.begin(), pairs.end(), [](const TrianglePair& x, const TrianglePair& y) {
            return std::tie(x.a, x.b) < std::tie(y.a, y.b);
          });
          if (reference.empty()) {
            reference = pairs;
            continue;
          }
          EXPECT_EQ(pairs.size(), reference.size());
          for (std::size_t i = 0; i < std::min(pairs.size(), reference.size()); ++i) {
            EXPECT_EQ(pairs[i].result.contact, reference[i].result.contact);
            EXPECT_EQ(pairs[i].result.a, reference[i].result.a);
            EXPECT_EQ(pairs[i].result.b, reference[i].result.b);
          }
        }
      }
    }
  }
  return {with_pairs, without};
}

TEST(BvhCollide, FindsExactlyTheBruteForcePairsForEveryScheduleAndPlacement) {
  const auto [with_pairs, without] = expect_brute_force_pairs(SeparatingAxisTest{}, 13);
  EXPECT_GT(with_pairs, 10);
  EXPECT_GT(without, 4);
}

TEST(BvhCollide, FindsExactlyTheBruteForcePairsWithTheProjectionTest) {
  const auto [with_pairs, without] = expect_brute_force_pairs(tri_tri_projection, 15);
  EXPECT_GT(with_pairs, 10);
  EXPECT_GT(without, 4);
}

// Boxes that only touch (at a corner, along an edge, over a face) meet in closed sets, and the
// hybrid schedules' circumsphere tests are then exactly tangent at the touching corner: far from
// the origin, where the tests' sums round relative to the coordinates' magnitude, no schedule may
// lose a touching pair. Sizes and offsets are dyadic, so the meshes touch exactly.
TEST(BvhCollide, TouchingBoxesFarFromTheOriginAreFoundByEverySchedule) {
  const Eigen::Vector3d size(0.375, 0.75, 0.5);
  const TriMesh box = box_surface(2, size);
  const Eigen::Vector3d touches[] = {size, Eigen::Vector3d(size.x(), size.y(), 0.0),
                                     Eigen::Vector3d(size.x(), 0.0, 0.0)};
  CollideBuffers buffers;
  std::vector<TrianglePair> pairs;
  for (const double offset : {0.0, 1024.125, -7340032.25, 1099511627776.5 /* 2^40 + 0.5 */}) {
    const Eigen::Matrix3Xd positions_a = box.vertices.array() + offset;
    for (const Eigen::Vector3d& touch : touches) {
      const Eigen::Matrix3Xd positions_b = (box.vertices.colwise() + touch).array() + offset;
      const auto expected =
          brute_force_pairs(box, positions_a, box, positions_b, tri_tri_projection);
      ASSERT_FALSE(expected.empty()) << "offset " << offset << ", touch " << touch.transpose();
      for (const NamedSchedule& schedule_a : schedules()) {
        Bvh tree_a(box.vertices, box.triangles, schedule_a.schedule);
        tree_a.refit(positions_a);
        for (const NamedSchedule& schedule_b : schedules()) {
          Bvh tree_b(box.vertices, box.triangles, schedule_b.schedule);
          tree_b.refit(positions_b);
          collide(tree_a, positions_a, tree_b, positions_b, buffers, pairs);
          EXPECT_EQ(sorted_indices(pairs), expected)
              << schedule_a.name << " vs " << schedule_b.name << ", offset " << offset << ", touch "
              << touch.transpose();
        }
      }
    }
  }
}

TEST(BvhCollide, EveryNamedMethodAgreesWithItsFunctionAndBatchedWithProjection) {
  std::mt19937 rng(16);
  TriMesh mesh_a = icosphere(3, 1.0);
  perturb_radially(mesh_a, 0.15, rng);
  const TriMesh mesh_b = box_surface(4, Eigen::Vector3d(0.5, 0.3, 0.6));
  const Bvh tree_a(mesh_a.vertices, mesh_a.triangles, BvhSchedule::liver());
  Bvh tree_b(mesh_b.vertices, mesh_b.triangles, BvhSchedule::instrument());
  CollideBuffers buffers;
  std::vector<TrianglePair> named, direct;
  int total = 0;
  for (const Placement& placement : placements(rng)) {
    const Eigen::Matrix3Xd positions_b =
        (placement.rotation * mesh_b.vertices).colwise() + placement.translation;
    tree_b.refit(positions_b);
    collide(tree_a, mesh_a.vertices, tree_b, positions_b, buffers, direct, nullptr,
            tri_tri_projection);
    for (const TriTriMethod method : {TriTriMethod::kProjection, TriTriMethod::kBatched}) {
      QueryStats stats;
      collide(tree_a, mesh_a.vertices, tree_b, positions_b, buffers, named, &stats, method);
      ASSERT_EQ(named.size(), direct.size());
      for (std::size_t i = 0; i < named.size(); ++i) {
        EXPECT_EQ(named[i].a, direct[i].a);
        EXPECT_EQ(named[i].b, direct[i].b);
        EXPECT_EQ(named[i].result.contact, direct[i].result.contact);
        EXPECT_EQ(named[i].result.a, direct[i].result.a);
        EXPECT_EQ(named[i].result.b, direct[i].result.b);
      }
      EXPECT_EQ(stats.pairs_found, static_cast<std::int64_t>(named.size()));
    }
    total += static_cast<int>(direct.size());
  }
  EXPECT_GT(total, 100);
}

TEST(BvhCollide, ReturnsTheTestsResultsAndSwappingTheTreesSwapsThePairs) {
  std::mt19937 rng(14);
  const TriMesh mesh_a = icosphere(2, 1.0);
  const TriMesh mesh_b = box_surface(3, Eigen::Vector3d(0.8, 0.8, 0.8));
  const Eigen::Matrix3Xd positions_b =
      (random_rotation(rng) * mesh_b.vertices).colwise() + Eigen::Vector3d(0.6, 0.1, 0.2);
  const Bvh tree_a(mesh_a.vertices, mesh_a.triangles, BvhSchedule::liver());
  Bvh tree_b(mesh_b.vertices, mesh_b.triangles, BvhSchedule::instrument());
  tree_b.refit(positions_b);
  CollideBuffers buffers;
  std::vector<TrianglePair> ab, ba;
  const SeparatingAxisTest test;
  collide(tree_a, mesh_a.vertices, tree_b, positions_b, buffers, ab, nullptr, test);
  collide(tree_b, positions_b, tree_a, mesh_a.vertices, buffers, ba, nullptr, test);
  ASSERT_FALSE(ab.empty());
  std::vector<std::pair<int, int>> swapped;
  for (const TrianglePair& pair : ba) {
    swapped.emplace_back(pair.b, pair.a);
  }
  std::sort(swapped.begin(), swapped.end());
  EXPECT_EQ(sorted_indices(ab), swapped);
  // Each pair carries the result the test gives for those two triangles.
  for (const TrianglePair& pair : ab) {
    const auto ta = mesh_a.triangles.col(pair.a);
    const auto tb = mesh_b.triangles.col(pair.b);
    const TriTriResult direct =
        test(mesh_a.vertices.col(ta(0)), mesh_a.vertices.col(ta(1)), mesh_a.vertices.col(ta(2)),
             positions_b.col(tb(0)), positions_b.col(tb(1)), positions_b.col(tb(2)));
    EXPECT_EQ(pair.result.contact, direct.contact);
    EXPECT_EQ(pair.result.a, direct.a);
    EXPECT_EQ(pair.result.b, direct.b);
  }
}

TEST(BvhCollide, BoxTieBreakerMakesTheHybridVisitNoMoreNodePairsThanTheAabbTree) {
  // The thesis's hybrid schedules decide sphere-level pairs whose spheres overlap by the box;
  // the all-sphere peer does not (it tests spheres only).
  EXPECT_TRUE(BvhSchedule::liver().box_tie_breaker);
  EXPECT_TRUE(BvhSchedule::instrument().box_tie_breaker);
  EXPECT_FALSE(BvhSchedule::all_sphere().box_tie_breaker);
  std::mt19937 rng(15);
  TriMesh mesh_a = icosphere(4, 1.0);  // 5120 triangles: 10 levels, the top 6 with spheres
  perturb_radially(mesh_a, 0.1, rng);
  const TriMesh mesh_b = box_surface(6, Eigen::Vector3d(0.05, 0.05, 1.5));  // a long thin probe
  CollideBuffers buffers;
  std::vector<TrianglePair> pairs;
  int placements_with_fewer = 0;
  for (const double offset : {1.2, 1.0, 0.9, 0.6}) {
    const Eigen::Matrix3Xd positions_b =
        (random_rotation(rng) * mesh_b.vertices).colwise() + Eigen::Vector3d(offset, 0.1, 0.0);
    QueryStats stats[3];
    const BvhSchedule liver[3] = {BvhSchedule::liver(), BvhSchedule::all_aabb(11),
                                  BvhSchedule::all_sphere(11)};
    const BvhSchedule tool[3] = {BvhSchedule::instrument(), BvhSchedule::all_aabb(9),
                                 BvhSchedule::all_sphere(9)};
    for (int k = 0; k < 3; ++k) {
      const Bvh tree_a(mesh_a.vertices, mesh_a.triangles, liver[k]);
      const Bvh tree_b(positions_b, mesh_b.triangles, tool[k]);
      collide(tree_a, mesh_a.vertices, tree_b, positions_b, buffers, pairs, &stats[k],
              SeparatingAxisTest{});
    }
    SCOPED_TRACE(offset);
    EXPECT_LE(stats[0].node_visits, stats[1].node_visits);
    EXPECT_EQ(stats[0].tri_tests, stats[1].tri_tests);  // the same leaf pairs, the same filter
    EXPECT_EQ(stats[0].pairs_found, stats[2].pairs_found);
    EXPECT_GT(stats[0].sphere_tests, 0);
    placements_with_fewer += stats[0].node_visits < stats[2].node_visits ? 1 : 0;
  }
  // Against the pure-sphere tree the boxes cut node visits.
  EXPECT_GT(placements_with_fewer, 0);
}

TEST(BvhCollide, RepeatedQueriesReuseTheBuffersAndEmptyTreesGiveNoPairs) {
  const TriMesh mesh = icosphere(2, 1.0);
  const Eigen::Matrix3Xd shifted = mesh.vertices.colwise() + Eigen::Vector3d(1.2, 0, 0);
  const Bvh tree_a(mesh.vertices, mesh.triangles, BvhSchedule::liver());
  const Bvh tree_b(shifted, mesh.triangles, BvhSchedule::liver());
  CollideBuffers buffers;
  std::vector<TrianglePair> pairs;
  collide(tree_a, mesh.vertices, tree_b, shifted, buffers, pairs, nullptr, SeparatingAxisTest{});
  ASSERT_FALSE(pairs.empty());
  const auto* const candidates = buffers.candidates.data();
  const auto* const results = pairs.data();
  for (int repeat = 0; repeat < 3; ++repeat) {
    collide(tree_a, mesh.vertices, tree_b, shifted, buffers, pairs, nullptr, SeparatingAxisTest{});
  }
  EXPECT_EQ(buffers.candidates.data(), candidates);
  EXPECT_EQ(pairs.data(), results);

  const Bvh empty(mesh.vertices, Eigen::Matrix3Xi(3, 0), BvhSchedule::liver());
  EXPECT_TRUE(empty.empty());
  collide(empty, mesh.vertices, tree_b, shifted, buffers, pairs, nullptr, SeparatingAxisTest{});
  EXPECT_TRUE(pairs.empty());
}

}  // namespace
}  // namespace softbench::collision
