// SPDX-License-Identifier: MIT
#pragma once

// Moeller's interval-overlap test (T. Moeller, "A fast triangle-triangle intersection test",
// JGT 2(2), 1997), the first peer of the projection method: signed distances of each
// triangle's vertices to the other's plane, then the two intervals where the triangles cut the
// line L = N1 x N2, projected on L's dominant axis; coplanar triangles by 2D edge tests and
// point-in-triangle on the dominant projection. The segment is the overlap of the intervals,
// as in the paper's tri_tri_intersect_with_isectline.
//
// Plain double without the paper's EPSILON snap (its absolute 1e-6 is scale-dependent: false
// positives for near-parallel and small triangles). Exact on generic input, not on shared
// vertices and edges, where rounding decides. Degenerate triangles are outside its contract
// (their zero normal sends them to the coplanar branch).

#include "collision/tri_tri_result.h"

namespace softbench::collision {

TriTriTest tri_tri_moller;

}  // namespace softbench::collision
