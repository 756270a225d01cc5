// SPDX-License-Identifier: MIT
#pragma once

#include "geometry/tet_mesh.h"

#include <Eigen/Core>

#include <vector>

namespace softbench {

/// A renumbering of a mesh's vertices: new_of_old[v] is old vertex v's new index, old_of_new its
/// inverse.
struct VertexOrder {
  std::vector<int> new_of_old;
  std::vector<int> old_of_new;
};

/// Reverse Cuthill-McKee (George and Liu 1981) over the tets' edges: a breadth-first numbering
/// from a vertex of least degree, each vertex's unnumbered neighbours taken by increasing degree,
/// reversed; each connected part in turn. Neighbours get nearby numbers, so what a vertex reads
/// of its neighbours (their values, the elements they share) lies close in memory. Mesh
/// generators number in no such order: TetGen's liver has a median |i - j| over its edges of 141
/// of 1215 vertices.
VertexOrder reverse_cuthill_mckee(const Eigen::Matrix4Xi& tets, int num_vertices);

/// An order whose vertices fall into `parts` ranges no edge joins, then one range (the separator)
/// holding every vertex that joins them: offsets has parts + 2 entries, part k being
/// [offsets[k], offsets[k + 1]) and the separator [offsets[parts], offsets[parts + 1] = #V).
/// What a Gauss-Seidel sweep needs to run on the parts side by side: no part reads another's
/// values, and the separator, swept after them (before them backwards), reads any.
struct PartitionedOrder {
  VertexOrder order;
  std::vector<int> offsets;
};

/// `tets`' vertices, numbered for locality (reverse_cuthill_mckee()), cut into `parts` ranges
/// of consecutive numbers; a vertex with a neighbour in an earlier range goes to the separator,
/// so no edge is left between two parts. In a breadth-first numbering a cut crosses the body
/// (the separator is about one level of the search: 8% of liver_x16's vertices in two parts),
/// and each part keeps its vertices' relative order. The cuts are placed so that the parts hold
/// equal work after their fronts leave for the separator, a vertex's work being its neighbours
/// and itself (the blocks of its row, which a sweep reads). parts <= 1: the given numbering, one part.
PartitionedOrder partitioned(const Eigen::Matrix4Xi& tets, int num_vertices, int parts);

/// `mesh` with its vertices numbered by `order` and its tets sorted by their smallest new vertex
/// (ties by the original order; each tet's own vertex order, and so its orientation, is kept):
/// the same body, vertex old_of_new[i] now numbered i.
TetMesh renumbered(const TetMesh& mesh, const VertexOrder& order);

}  // namespace softbench
