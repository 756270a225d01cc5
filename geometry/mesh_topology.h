// SPDX-License-Identifier: MIT
#pragma once

#include "geometry/tet_mesh.h"
#include "geometry/tri_mesh.h"

#include <Eigen/Core>

#include <span>
#include <vector>

namespace softbench {

/// The boundary of a tet mesh: faces used by exactly one tet, oriented outward (counter-clockwise
/// seen from outside, given the TetMesh's positive orientation), indexing the tet mesh's
/// vertices, sorted for determinism.
Eigen::Matrix3Xi boundary_triangles(const Eigen::Matrix4Xi& tets);

/// The boundary as a stand-alone surface: only the vertices it uses, renumbered in increasing
/// order of their tet-mesh index; `tet_vertex_of[i]` (if given) is the tet-mesh index of surface
/// vertex i.
TriMesh boundary_surface(const TetMesh& mesh, std::vector<int>* tet_vertex_of = nullptr);

/// Unique undirected edges, each as (smaller, larger) index, sorted lexicographically.
Eigen::Matrix2Xi unique_edges(const Eigen::Matrix4Xi& tets);  ///< 2 x #E
Eigen::Matrix2Xi unique_edges(const Eigen::Matrix3Xi& triangles);
/// The column of edge (i, j), i < j, in `edges` as unique_edges returns them (binary search);
/// where the edge is absent, the column it would be inserted at.
int edge_index(const Eigen::Matrix2Xi& edges, int i, int j);

/// Items grouped by their owners, as CSR: owner o's items are items[offsets[o] .. offsets[o + 1]),
/// increasing. Item k belongs to owners[k] (a tet corner 4 t + a to its vertex, a triangle's side
/// 3 t + k to its edge); `num_owners` bounds the owners.
struct Incidences {
  std::vector<int> offsets;  ///< num_owners + 1
  std::vector<int> items;
};
Incidences group_by_owner(std::span<const int> owners, int num_owners);

/// Per vertex, the tet corners at it (4 * tet + the local index 0..3), in tet order: vertex v's
/// are items[offsets[v] .. offsets[v + 1]). A per-vertex gather of per-element terms walks them,
/// and sums in the same order whatever thread does it.
Incidences vertex_corners(const Eigen::Matrix4Xi& tets, int num_vertices);

/// Edge-based topology of a triangle surface.
struct SurfaceTopology {
  int boundary_edges = 0;        ///< edges used by one triangle (open surface)
  int non_manifold_edges = 0;    ///< edges used by three or more triangles
  int misoriented_edges = 0;     ///< edges two triangles traverse in the same direction
  int components = 0;            ///< connected components (through shared vertices)
  int euler_characteristic = 0;  ///< V - E + F over referenced vertices
  int unreferenced_vertices = 0;

  bool closed_manifold() const { return boundary_edges == 0 && non_manifold_edges == 0; }
  bool oriented() const { return misoriented_edges == 0; }
};
SurfaceTopology surface_topology(const Eigen::Matrix3Xi& triangles, int num_vertices);

}  // namespace softbench
