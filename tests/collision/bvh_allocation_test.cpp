// SPDX-License-Identifier: MIT
// The BVH's steady state allocates nothing: once a query's buffers have grown to the contact it
// meets, refit and query (every narrow-phase method) only reuse them. Global operator new is
// replaced by a counting one (counting_operator_new.cpp), so this test is its own executable.
#include "collision/bvh.h"
#include "collision/bvh_collide.h"
#include "collision/bvh_schedule.h"
#include "tests/collision/bvh_test_meshes.h"
#include "tests/collision/counting_operator_new.h"

#include <Eigen/Core>
#include <gtest/gtest.h>

#include <cmath>
#include <vector>

namespace softbench::collision {
namespace {

using test::icosphere;

// Two spheres in contact, the second breathing and sliding so that the contact changes from
// frame to frame, but never beyond what the warm-up frames (the same motion) met.
Eigen::Matrix3Xd frame_positions(const Eigen::Matrix3Xd& rest, int frame) {
  const double phase = 0.3 * (frame % 8);
  Eigen::Matrix3Xd moved = rest * (1.0 + 0.02 * std::sin(phase));
  moved.row(0).array() += 1.6 + 0.05 * std::cos(phase);
  return moved;
}

TEST(BvhAllocation, RefitAndQueryAllocateNothingOnceTheBuffersHaveGrown) {
  const TriMesh a = icosphere(3, 1.0);
  const TriMesh b = icosphere(3, 0.8);
  Bvh tree_a(a.vertices, a.triangles, BvhSchedule::liver());
  Bvh tree_b(b.vertices, b.triangles, BvhSchedule::instrument());
  CollideBuffers buffers;
  std::vector<TrianglePair> pairs;
  Eigen::Matrix3Xd moved = b.vertices;
  const TriTriMethod methods[] = {TriTriMethod::kProjection, TriTriMethod::kMoller,
                                  TriTriMethod::kGuigue, TriTriMethod::kBatched};
  auto run_frames = [&](int first, int count) {
    std::size_t found = 0;
    for (int frame = first; frame < first + count; ++frame) {
      moved = frame_positions(b.vertices, frame);  // same size: assigned in place
      tree_b.refit(moved);
      tree_a.refit(a.vertices);
      for (const TriTriMethod method : methods) {
        collide(tree_a, a.vertices, tree_b, moved, buffers, pairs, nullptr, method);
        found += pairs.size();
      }
    }
    return found;
  };
  ASSERT_GT(run_frames(0, 8), 0u);  // warm-up: every buffer grows to the largest contact
  const long before = softbench::test::allocation_count();
  const std::size_t found = run_frames(8, 16);
  EXPECT_EQ(softbench::test::allocation_count() - before, 0);
  EXPECT_GT(found, 0u);
  // The counter counts: a fresh buffer does allocate.
  CollideBuffers fresh;
  collide(tree_a, a.vertices, tree_b, moved, fresh, pairs);
  EXPECT_GT(softbench::test::allocation_count() - before, 0);
}

}  // namespace
}  // namespace softbench::collision
