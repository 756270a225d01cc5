// SPDX-License-Identifier: MIT
#pragma once

#include "geometry/mesh_data.h"
#include "geometry/mesh_measures.h"
#include "geometry/mesh_topology.h"
#include "geometry/mesh_validation.h"

#include <nlohmann/json.hpp>

#include <optional>
#include <string>
#include <utility>
#include <vector>

namespace softbench::harness {

/// What `softbench mesh info` reports about one mesh file. Counts follow the thesis's (section
/// 2.5.5: "1206 vertices, 4230 tets, 9313 triangles, 6288 edges"), so a generated liver can be
/// compared with it directly.
struct MeshInfo {
  std::string source;
  int vertices = 0;
  int triangles = 0;  ///< the file's triangles, or the tet boundary's if it has none
  bool triangles_from_boundary = false;
  int tetrahedra = 0;
  int faces = 0;  ///< distinct triangular faces of the tets (0 without tets)
  int edges = 0;  ///< distinct edges of the tets, else of the triangles
  Eigen::Matrix<double, 3, 2> bbox = Eigen::Matrix<double, 3, 2>::Zero();
  std::optional<double> volume;  ///< of the tets, or enclosed by a closed surface
  std::optional<double> surface_area;
  SurfaceTopology surface;            ///< of `triangles`
  std::optional<TetQuality> quality;  ///< with tets only
  /// Pairs of `triangles` that intersect other than where the surface joins them
  /// (find_self_intersections); each is an error, as TetGen refuses such a surface.
  int self_intersecting_pairs = 0;
  std::vector<MeshProblem> problems;

  /// No error-severity problem: the mesh can be simulated (tets) or collided with (surface).
  bool usable() const;
};

/// The triangle pairs of a surface that intersect where the surface does not join them.
struct SelfIntersections {
  int pairs = 0;
  std::vector<std::pair<int, int>> examples;  ///< the first few pairs found, triangle indices
};

/// Every pair of `triangles` (3 x #T, into `vertices`, 3 x #V) that intersects other than where
/// the two are joined: candidate pairs from a BVH over the surface (collision/bvh_collide.h),
/// each decided by the exact projection test (collision/tri_tri_projection.h) and exact
/// orientation signs. Triangles that share vertices (same index or same position) touch there,
/// which is not an intersection; they count only where they genuinely cross or overlap:
///  - one shared vertex: when the edge opposite it in either meets the other triangle (what
///    they share is convex and holds the vertex; any other corner of it lies on such an edge);
///  - one shared edge: when the two lie in one plane on the same side of it (folded over);
///  - three shared vertices: a duplicated triangle.
/// Touching counts as intersecting (the tests are closed), as for TetGen. A pair where a
/// triangle of zero area shares a vertex is left out (validation reports zero-area triangles).
SelfIntersections find_self_intersections(const Eigen::Matrix3Xd& vertices,
                                          const Eigen::Matrix3Xi& triangles,
                                          int max_examples = 5);

/// Inspects a mesh as read from a file: never throws for geometric problems, it lists them
/// (including a self-intersecting surface, the file's triangles or the tets' boundary).
MeshInfo inspect_mesh(const MeshData& data);

nlohmann::json to_json(const MeshInfo& info);
/// Human-readable, one fact per line: "vertices: 1206", "tetrahedra: 4230", ...
std::string to_text(const MeshInfo& info);

}  // namespace softbench::harness
