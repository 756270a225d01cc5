// SPDX-License-Identifier: MIT
#pragma once

#include "geometry/mesh_data.h"
#include "geometry/tri_mesh.h"

namespace softbench::meshgen {

/// Quality-bounded Delaunay tetrahedralization of a closed surface by TetGen (Si 2015), the step
/// the thesis does with QTetraMesher (section 2.5.5), which wraps TetGen too.
struct TetrahedralizeOptions {
  /// Upper bound on a tet's volume, m^3; 0 for none. Smaller: more tets, slower models.
  double max_volume = 0.0;
  /// Upper bound on a tet's circumradius-to-shortest-edge ratio (TetGen -q); >= 1.1. Smaller:
  /// better-shaped tets (stiffness matrices better conditioned) but more Steiner points.
  double radius_edge_ratio = 1.5;
  /// Target lower bound on dihedral angles, degrees (TetGen -q<ratio>/<angle>); 0 keeps TetGen's
  /// default (none). The radius-edge bound alone lets slivers through (min dihedral ~3 deg on the
  /// liver). A target, not a guarantee: TetGen splits the tets below it but may leave some (it
  /// rejects split points that encroach on the preserved surface; a tight ratio competes with
  /// it), so callers measure the result (`mesh tetrahedralize` warns when it falls short).
  double min_dihedral_deg = 12.0;
  /// Keep the input surface triangles as they are (TetGen -Y): the simulation's surface then is
  /// exactly the given one, at the price of less freedom for quality near the boundary.
  bool preserve_surface = true;
};

/// Tetrahedralizes `surface` (closed, manifold, outward). The result's tets are positively
/// oriented (TetMesh convention) and its triangles are the boundary faces TetGen reports.
/// Throws InputError when TetGen refuses the surface (self-intersections, degenerate facets).
MeshData tetrahedralize(const TriMesh& surface, const TetrahedralizeOptions& options = {});

}  // namespace softbench::meshgen
