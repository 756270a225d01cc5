// SPDX-License-Identifier: MIT
#pragma once

// Test data for the triangle-triangle tests: the designed pairs (every case of the thesis's
// figure 4.14 and every singular contact, with hand-derived answers), random pairs (the recipe
// at random_pairs) and near-degenerate families. Deterministic (fixed seeds).

#include "collision/tri_tri_result.h"

#include <Eigen/Core>

#include <array>
#include <cstddef>
#include <cstdint>
#include <string>
#include <vector>

namespace softbench::collision::test {

struct TriPair {
  std::array<Eigen::Vector3d, 3> a;
  std::array<Eigen::Vector3d, 3> b;
};

struct DesignedPair {
  std::string label;        ///< what the pair exercises, e.g. "(f) pierce: L_B inside A"
  std::string figure_case;  ///< "a".."f" of figure 4.14 (B against A's plane), or "degenerate"
  TriPair pair;
  TriTriContact expected;  ///< derived by hand (the oracle confirms it in a test)
};

/// At least 40 pairs. Most use A = (0.5, 1.5, 0), (0, 0, 0), (2, 0, 0), whose computation frame
/// is the world frame (P1 at the origin, x* = x, z* = z), so A_v = [0, 1.5] on y, A_w = [0, 2]
/// on x and each case can be placed to be rejected on V, rejected on W, or decided in H.
std::vector<DesignedPair> designed_pairs();

/// `count` random pairs: A's centre uniform in the unit cube, vertices jittered by
/// +-0.1; B centred at A's centroid + U[-0.05, 0.05]^3, vertices +-0.1, clamped to the cube.
/// About 30 % intersect.
std::vector<TriPair> random_pairs(std::size_t count, std::uint64_t seed);

struct PairFamily {
  std::string name;
  /// The family is built from proper triangles (degenerate ones can still occur on the grids).
  std::vector<TriPair> pairs;
};

/// Near-degenerate families of `count` pairs each: vertices snapped (rounded) onto the other's
/// plane, an edge snapped into it, edges crossing exactly (integer grid), mesh neighbours sharing
/// an edge or a vertex, exactly coplanar integer triangles, an integer grid with many touches,
/// near-parallel planes.
std::vector<PairFamily> near_degenerate_families(std::size_t count, std::uint64_t seed);

}  // namespace softbench::collision::test
