// SPDX-License-Identifier: MIT
#pragma once

#include "geometry/mesh_data.h"
#include "geometry/tri_mesh.h"

#include <vector>

namespace softbench {

// Meshes made in code, for analytic checks that must not depend on a file: tensor-product boxes
// of tets and a sphere surface. The tests' small meshes (tests/test_meshes.h) build theirs here.

/// A box split along each axis at the given coordinates (each strictly increasing, at least two
/// values): (#x - 1)(#y - 1)(#z - 1) cells, each split into 6 tets along its main diagonal
/// (Kuhn's split). Every cell uses the same diagonal direction, so neighbouring cells share face
/// diagonals: the mesh is conforming however the spacing varies. Tets positively oriented.
/// Vertex (i, j, k) has index i + #x (j + #y k).
MeshData grid_box_tets(const std::vector<double>& xs,
                       const std::vector<double>& ys,
                       const std::vector<double>& zs);

/// The box [0,lx]x[0,ly]x[0,lz] in nx*ny*nz equal cells (grid_box_tets).
MeshData box_tets(int nx, int ny, int nz, double lx = 1.0, double ly = 1.0, double lz = 1.0);

/// An icosahedron subdivided `levels` times (20 * 4^levels triangles), its vertices projected
/// onto the sphere of `radius` about the origin. Closed and outward oriented.
TriMesh icosphere(int levels, double radius = 1.0);

}  // namespace softbench
