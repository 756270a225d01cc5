// SPDX-License-Identifier: MIT
#include "collision/bvh_collide.h"

#include "collision/tri_tri_guigue.h"
#include "collision/tri_tri_moller.h"
#include "collision/tri_tri_projection.h"

#include <algorithm>
#include <array>
#include <utility>

namespace softbench::collision {
namespace {

/// Runs the tests the two nodes' kinds share, cheapest first (see bvh_collide.h). `magnitude`
/// bounds every coordinate of both trees (circumspheres_overlap).
bool volumes_overlap(const BvhNode& a, const BvhNode& b, double magnitude, QueryStats& stats) {
  if (a.has_sphere() && b.has_sphere()) {
    ++stats.sphere_tests;
    const bool spheres_overlap = a.has_box() && b.has_box()
                                     ? circumspheres_overlap(a.box, b.box, magnitude)
                                     : overlap(a.sphere_of(), b.sphere_of());
    if (!spheres_overlap) {
      return false;
    }
  }
  if (a.has_box() && b.has_box()) {
    return overlap(a.box, b.box);
  }
  if (a.has_sphere() && b.has_box()) {
    return overlap(a.sphere, b.box);
  }
  if (a.has_box() && b.has_sphere()) {
    return overlap(a.box, b.sphere);
  }
  return true;  // both sphere-only, and the spheres overlap
}

Aabb triangle_box(const Eigen::Matrix3Xd& positions, const Eigen::Matrix3Xi& slots, int slot) {
  const auto p0 = positions.col(slots(0, slot));
  const auto p1 = positions.col(slots(1, slot));
  const auto p2 = positions.col(slots(2, slot));
  Aabb box;
  box.min = p0.cwiseMin(p1).cwiseMin(p2);
  box.max = p0.cwiseMax(p1).cwiseMax(p2);
  return box;
}

double box_size(const BvhNode& node) {
  return node.box.extent().squaredNorm();
}

void leaf_pair(const Bvh& tree_a,
               const Eigen::Matrix3Xd& positions_a,
               const BvhNode& leaf_a,
               const Bvh& tree_b,
               const Eigen::Matrix3Xd& positions_b,
               const BvhNode& leaf_b,
               CollideBuffers& buffers) {
  const Eigen::Matrix3Xi& slots_a = tree_a.slot_vertices();
  const Eigen::Matrix3Xi& slots_b = tree_b.slot_vertices();
  buffers.kept_slots.clear();
  buffers.kept_boxes.clear();
  for (int sb = leaf_b.first; sb < leaf_b.first + leaf_b.count; ++sb) {
    const Aabb box = triangle_box(positions_b, slots_b, sb);
    if (overlap(box, leaf_a.box)) {
      buffers.kept_slots.push_back(sb);
      buffers.kept_boxes.push_back(box);
    }
  }
  if (!buffers.kept_slots.empty()) {
    for (int sa = leaf_a.first; sa < leaf_a.first + leaf_a.count; ++sa) {
      const Aabb box = triangle_box(positions_a, slots_a, sa);
      if (!overlap(box, leaf_b.box)) {
        continue;
      }
      for (std::size_t k = 0; k < buffers.kept_slots.size(); ++k) {
        if (overlap(box, buffers.kept_boxes[k])) {
          buffers.candidates.push_back({sa, buffers.kept_slots[k]});
        }
      }
    }
  }
}

}  // namespace

void collect_candidates(const Bvh& tree_a,
                        const Eigen::Matrix3Xd& positions_a,
                        const Bvh& tree_b,
                        const Eigen::Matrix3Xd& positions_b,
                        CollideBuffers& buffers,
                        QueryStats& stats) {
  buffers.candidates.clear();
  if (tree_a.empty() || tree_b.empty()) {
    return;
  }
  // Each step pops one pair and pushes at most two, each one level deeper in one tree, so the
  // stack never holds more than levels_a + levels_b entries.
  std::array<std::pair<int, int>, 2 * BvhSchedule::kMaxLevels + 2> stack;
  int top = 0;
  stack[static_cast<std::size_t>(top++)] = {0, 0};
  const std::vector<BvhNode>& nodes_a = tree_a.nodes();
  const std::vector<BvhNode>& nodes_b = tree_b.nodes();
  const double magnitude = std::max(tree_a.coordinate_magnitude(), tree_b.coordinate_magnitude());
  while (top > 0) {
    const auto [index_a, index_b] = stack[static_cast<std::size_t>(--top)];
    const BvhNode& a = nodes_a[static_cast<std::size_t>(index_a)];
    const BvhNode& b = nodes_b[static_cast<std::size_t>(index_b)];
    ++stats.node_visits;
    if (!volumes_overlap(a, b, magnitude, stats)) {
      continue;
    }
    if (a.is_leaf() && b.is_leaf()) {
      ++stats.leaf_visits;
      leaf_pair(tree_a, positions_a, a, tree_b, positions_b, b, buffers);
      continue;
    }
    const bool descend_a = b.is_leaf() || (!a.is_leaf() && box_size(a) >= box_size(b));
    if (descend_a) {
      stack[static_cast<std::size_t>(top++)] = {a.first + 1, index_b};
      stack[static_cast<std::size_t>(top++)] = {a.first, index_b};
    } else {
      stack[static_cast<std::size_t>(top++)] = {index_a, b.first + 1};
      stack[static_cast<std::size_t>(top++)] = {index_a, b.first};
    }
  }
}

namespace {

void narrow_phase_batched(const Bvh& tree_a,
                          const Eigen::Matrix3Xd& positions_a,
                          const Bvh& tree_b,
                          const Eigen::Matrix3Xd& positions_b,
                          CollideBuffers& buffers,
                          std::vector<TrianglePair>& pairs) {
  pairs.clear();
  buffers.batch_a.clear();
  buffers.batch_b.clear();
  const Eigen::Matrix3Xi& slots_a = tree_a.slot_vertices();
  const Eigen::Matrix3Xi& slots_b = tree_b.slot_vertices();
  for (const CandidatePair& candidate : buffers.candidates) {
    const auto ta = slots_a.col(candidate.slot_a);
    const auto tb = slots_b.col(candidate.slot_b);
    buffers.batch_a.push_back(positions_a.col(ta(0)), positions_a.col(ta(1)),
                              positions_a.col(ta(2)));
    buffers.batch_b.push_back(positions_b.col(tb(0)), positions_b.col(tb(1)),
                              positions_b.col(tb(2)));
  }
  buffers.batch_hit.resize(buffers.candidates.size());
  tri_tri_batch(buffers.batch_a, buffers.batch_b, buffers.batch_hit);
  for (std::size_t i = 0; i < buffers.candidates.size(); ++i) {
    if (buffers.batch_hit[i] == 0) {
      continue;
    }
    const CandidatePair& candidate = buffers.candidates[i];
    const TriTriResult result = tri_tri_projection(
        buffers.batch_a.vertex(i, 0), buffers.batch_a.vertex(i, 1), buffers.batch_a.vertex(i, 2),
        buffers.batch_b.vertex(i, 0), buffers.batch_b.vertex(i, 1), buffers.batch_b.vertex(i, 2));
    pairs.push_back(
        {tree_a.slot_triangle(candidate.slot_a), tree_b.slot_triangle(candidate.slot_b), result});
  }
}

}  // namespace

void narrow_phase(const Bvh& tree_a,
                  const Eigen::Matrix3Xd& positions_a,
                  const Bvh& tree_b,
                  const Eigen::Matrix3Xd& positions_b,
                  CollideBuffers& buffers,
                  std::vector<TrianglePair>& pairs,
                  TriTriMethod method) {
  const std::vector<CandidatePair>& candidates = buffers.candidates;
  switch (method) {
    case TriTriMethod::kProjection:
      narrow_phase(tree_a, positions_a, tree_b, positions_b, candidates, pairs, tri_tri_projection);
      return;
    case TriTriMethod::kMoller:
      narrow_phase(tree_a, positions_a, tree_b, positions_b, candidates, pairs, tri_tri_moller);
      return;
    case TriTriMethod::kGuigue:
      narrow_phase(tree_a, positions_a, tree_b, positions_b, candidates, pairs, tri_tri_guigue);
      return;
    case TriTriMethod::kBatched:
      narrow_phase_batched(tree_a, positions_a, tree_b, positions_b, buffers, pairs);
      return;
  }
}

}  // namespace softbench::collision
