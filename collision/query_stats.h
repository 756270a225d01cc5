// SPDX-License-Identifier: MIT
#pragma once

#include <cstdint>

namespace softbench::collision {

/// What one BVH query did (box2d's query counters): the cost model of a traversal, so that a
/// benchmark can say why one tree is faster than another, not only that it is.
struct QueryStats {
  std::int64_t node_visits = 0;   ///< node pairs (or nodes, for point queries) examined
  std::int64_t sphere_tests = 0;  ///< sphere-sphere tests run
  std::int64_t leaf_visits = 0;   ///< leaf pairs (or leaves) reached
  std::int64_t tri_tests = 0;     ///< exact triangle-triangle (or point-triangle) tests
  std::int64_t pairs_found = 0;   ///< intersecting triangle pairs reported
};

}  // namespace softbench::collision
