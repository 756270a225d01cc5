// SPDX-License-Identifier: MIT
#pragma once

#include <cstdint>

namespace softbench::collision {

/// What one BVH query did (box2d's query counters): the cost model of a traversal, so that a
/// benchmark can say why one tree is faster than another, not only that it is.
struct QueryStats {
  std::int64_t node_visits = 0;   ///< node pairs (or nodes, for point queries) examined
  std::int64_t sphere_tests = 0;  ///< sphere-sphere tests run
  std::int64_t box_tests = 0;     ///< box-box tests run
  std::int64_t mixed_tests = 0;   ///< sphere-box tests (nodes with no volume kind in common)
  std::int64_t leaf_visits = 0;   ///< leaf pairs (or leaves) reached
  std::int64_t triangle_boxes_culled = 0;  ///< triangle pairs rejected by their boxes in a leaf
  std::int64_t tri_tests = 0;              ///< exact triangle-triangle (or point-triangle) tests
  std::int64_t pairs_found = 0;            ///< intersecting triangle pairs reported

  QueryStats& operator+=(const QueryStats& other) {
    node_visits += other.node_visits;
    sphere_tests += other.sphere_tests;
    box_tests += other.box_tests;
    mixed_tests += other.mixed_tests;
    leaf_visits += other.leaf_visits;
    triangle_boxes_culled += other.triangle_boxes_culled;
    tri_tests += other.tri_tests;
    pairs_found += other.pairs_found;
    return *this;
  }
};

}  // namespace softbench::collision
