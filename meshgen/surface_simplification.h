// SPDX-License-Identifier: MIT
#pragma once

#include "geometry/tri_mesh.h"

namespace softbench::meshgen {

/// Reduces a closed manifold surface to about `target_vertices` vertices of well-shaped
/// triangles: edge collapse with the Lindstrom-Turk cost and placement (memoryless, volume-
/// preserving, no normal flips) down to twice the target, then isotropic remeshing (Botsch &
/// Kobbelt 2004: split, collapse, flip, tangential relaxation, projection onto the input) to an
/// edge length that gives the target count. CGAL's implementations (GPL, so they stay in
/// meshgen): robust edge collapse and remeshing are what a well-kept library does well.
/// The input must be closed and manifold; the output is too, with the same orientation.
TriMesh simplify_surface(const TriMesh& surface, int target_vertices);

}  // namespace softbench::meshgen
