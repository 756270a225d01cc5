// SPDX-License-Identifier: MIT
// Tree-vs-tree query: every intersecting triangle pair between two meshes, each with its BVH
// refitted to the positions passed here. Two phases:
//   1. broad phase (collect_candidates): simultaneous descent of both trees with an explicit
//      fixed-size stack (depth is bounded by the schedules, so no allocation), descending the
//      node with the larger box diagonal (on table 4.2's scenes it visits fewer node pairs than
//      the extent sum or the longest side); node pairs are tested with the volumes their kinds
//      share (sphere first as the early-out, then box; a sphere level of a schedule with
//      box_tie_breaker counts as sharing the box, so the hybrid tree never visits more node pairs
//      than the AABB tree; a sphere-only node against a box node uses the exact sphere-box test).
//      In a leaf pair, each triangle's box is tested against the other leaf's box
//      and then against the other triangles' boxes (same for every schedule: it is a leaf-level
//      filter, not a tree level). Survivors go to a caller-owned candidate buffer.
//   2. narrow phase: the exact triangle-triangle test on each candidate.
// Every volume and box test is closed and conservative, so the pairs reported are exactly those
// for which the narrow-phase test says "intersect" over all #T_a x #T_b pairs (the tests check
// this against brute force). A rigid instrument is passed in world coordinates (refit it after it
// moves); there is no per-query transform.
#pragma once

#include "collision/bvh.h"
#include "collision/query_stats.h"
#include "collision/tri_tri_batch.h"
#include "collision/tri_tri_result.h"

#include <Eigen/Core>

#include <type_traits>
#include <vector>

namespace softbench::collision {

/// One intersecting pair: triangle indices into each mesh's triangle matrix, and the test's
/// result (segment or coplanar flag).
struct TrianglePair {
  int a = -1;
  int b = -1;
  TriTriResult result;
};

/// A candidate from the broad phase, as slots of each tree (Bvh::slot_vertices()).
struct CandidatePair {
  int slot_a = -1;
  int slot_b = -1;
};

/// Buffers a caller keeps across queries so that a query allocates only while they grow.
struct CollideBuffers {
  std::vector<CandidatePair> candidates;
  std::vector<int> kept_slots;  ///< per leaf pair: triangles of leaf B near leaf A
  std::vector<Aabb> kept_boxes;
  TriangleSoA batch_a, batch_b;  ///< TriTriMethod::kBatched: the candidates, gathered
  std::vector<std::uint8_t> batch_hit;
};

/// The narrow-phase tests by name. kBatched runs the structure-of-arrays filter
/// (collision/tri_tri_batch.h, same answers as the projection test) over all candidates, then
/// the projection test on its hits for their segments.
enum class TriTriMethod : std::uint8_t { kProjection, kMoller, kGuigue, kBatched };

/// Broad phase. `positions_a` / `positions_b` (3 x #V) must be those the trees were last
/// refitted to. Fills buffers.candidates (cleared first) and adds to `stats`.
void collect_candidates(const Bvh& tree_a,
                        const Eigen::Matrix3Xd& positions_a,
                        const Bvh& tree_b,
                        const Eigen::Matrix3Xd& positions_b,
                        CollideBuffers& buffers,
                        QueryStats& stats);

/// Narrow phase: `test(p0, p1, p2, q0, q1, q2) -> TriTriResult` (all const Eigen::Vector3d&)
/// on each of `candidates`; `pairs` is cleared, then holds the intersecting ones in candidate
/// order, as mesh triangle indices.
template <class TriTriTest>
void narrow_phase(const Bvh& tree_a,
                  const Eigen::Matrix3Xd& positions_a,
                  const Bvh& tree_b,
                  const Eigen::Matrix3Xd& positions_b,
                  const std::vector<CandidatePair>& candidates,
                  std::vector<TrianglePair>& pairs,
                  TriTriTest&& test) {
  pairs.clear();
  const Eigen::Matrix3Xi& slots_a = tree_a.slot_vertices();
  const Eigen::Matrix3Xi& slots_b = tree_b.slot_vertices();
  for (const CandidatePair& candidate : candidates) {
    const auto ta = slots_a.col(candidate.slot_a);
    const auto tb = slots_b.col(candidate.slot_b);
    const Eigen::Vector3d p0 = positions_a.col(ta(0)), p1 = positions_a.col(ta(1)),
                          p2 = positions_a.col(ta(2));
    const Eigen::Vector3d q0 = positions_b.col(tb(0)), q1 = positions_b.col(tb(1)),
                          q2 = positions_b.col(tb(2));
    const TriTriResult result = test(p0, p1, p2, q0, q1, q2);
    if (result.intersect()) {
      pairs.push_back(
          {tree_a.slot_triangle(candidate.slot_a), tree_b.slot_triangle(candidate.slot_b), result});
    }
  }
}

/// Narrow phase by name on buffers.candidates (kBatched: the structure-of-arrays filter, then the
/// projection test on its hits for their segments); `pairs` as for the template above.
void narrow_phase(const Bvh& tree_a,
                  const Eigen::Matrix3Xd& positions_a,
                  const Bvh& tree_b,
                  const Eigen::Matrix3Xd& positions_b,
                  CollideBuffers& buffers,
                  std::vector<TrianglePair>& pairs,
                  TriTriMethod method);

/// Broad phase, then the narrow phase with `test`: a TriTriMethod (default: the thesis's
/// projection test) or a callable as narrow_phase() takes. `pairs` is cleared, then holds every
/// intersecting pair in traversal order. `stats` (optional) is overwritten with this query's
/// counts.
template <class TriTriTest = TriTriMethod>
void collide(const Bvh& tree_a,
             const Eigen::Matrix3Xd& positions_a,
             const Bvh& tree_b,
             const Eigen::Matrix3Xd& positions_b,
             CollideBuffers& buffers,
             std::vector<TrianglePair>& pairs,
             QueryStats* stats = nullptr,
             TriTriTest&& test = TriTriMethod::kProjection) {
  QueryStats counts;
  collect_candidates(tree_a, positions_a, tree_b, positions_b, buffers, counts);
  if constexpr (std::is_same_v<std::remove_cvref_t<TriTriTest>, TriTriMethod>) {
    narrow_phase(tree_a, positions_a, tree_b, positions_b, buffers, pairs, test);
  } else {
    narrow_phase(tree_a, positions_a, tree_b, positions_b, buffers.candidates, pairs, test);
  }
  counts.tri_tests = static_cast<std::int64_t>(buffers.candidates.size());
  counts.pairs_found = static_cast<std::int64_t>(pairs.size());
  if (stats != nullptr) {
    *stats = counts;
  }
}

}  // namespace softbench::collision
