// SPDX-License-Identifier: MIT
#pragma once

#include "geometry/tet_mesh.h"

#include <Eigen/Core>

#include <cstdint>
#include <optional>
#include <span>

namespace softbench::harness {

// The shapes `softbench stability` forces a body into before letting it recover (its torture
// cases). Each takes the rest positions (3 x #V, m) and returns the tortured ones
// (3 x #V, m), vertex for vertex. The centroid is the unweighted mean of the vertices; the axes
// are those of the rest bounding box.

/// Every vertex projected onto the plane through the centroid normal to the bounding box's
/// shortest axis (the thinnest direction: the squash a press would do). Every tet ends with
/// zero volume.
Eigen::Matrix3Xd squashed_to_plane(const Eigen::Matrix3Xd& rest);

/// Every vertex moved into a ball of radius `radius_fraction` x the bounding-box diagonal
/// around the centroid, uniformly at random (seeded): a collapse to a point that keeps the
/// vertices distinct, so no model meets an exactly zero matrix, only a 1e-9-volume one.
Eigen::Matrix3Xd collapsed_to_point(const Eigen::Matrix3Xd& rest,
                                    double radius_fraction,
                                    std::uint64_t seed);

/// Every vertex moved to a uniformly random point of the rest bounding box (seeded): about
/// half the tets end inverted.
Eigen::Matrix3Xd scrambled(const Eigen::Matrix3Xd& rest, std::uint64_t seed);

/// Stretched by `factor` along the bounding box's longest axis about the centroid; the other
/// coordinates are kept.
Eigen::Matrix3Xd stretched(const Eigen::Matrix3Xd& rest, double factor);

/// A mesh with one tet flattened into a near-degenerate one (radius ratio `quality`, 1 for a
/// regular tet), and which one.
struct Sliver {
  TetMesh mesh;
  int tet = -1;
  int vertex = -1;                 ///< the vertex moved toward the opposite face
  double moved = 0.0;              ///< m, how far it moved
  double quality = 0.0;            ///< the sliver's radius ratio after the move
  double neighbour_quality = 0.0;  ///< the worst radius ratio of the other tets around the vertex
};

/// `mesh` with one vertex moved toward the opposite face of one of its tets until that tet's
/// radius ratio is `quality`. Of all (tet, vertex) choices with the vertex not in `keep` (e.g.
/// the fixed region), the one whose move shrinks the other tets around the vertex least; the
/// others stay positively oriented. Empty when no choice keeps them so.
std::optional<Sliver> flatten_one_tet(const TetMesh& mesh,
                                      std::span<const int> keep,
                                      double quality);

}  // namespace softbench::harness
