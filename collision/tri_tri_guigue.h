// SPDX-License-Identifier: MIT
#pragma once

// Guigue and Devillers' test (P. Guigue, O. Devillers, "Fast and robust triangle-triangle
// overlap test using orientation predicates", JGT 8(1), 2003), the second peer: only signs of
// orient3d determinants. A circular permutation makes p1 (resp. p2) the vertex alone on its
// side of the other's plane, and two more orient3d decide whether the intervals on the
// intersection line overlap. Coplanar pairs go to edge-crossing plus containment tests with
// orient2d on the dominant projection (not the paper's 2D decision tree). The segment is built
// after the decision from the plane distances on the canonical edges.
//
// Plain double determinants, as the peers are measured (bench/tri_tri_bench.cpp): exact on
// generic input, wrong on part of the shared-vertex and shared-edge pairs where rounding
// decides; degenerate triangles are outside its contract.

#include "collision/tri_tri_result.h"

namespace softbench::collision {

TriTriTest tri_tri_guigue;

}  // namespace softbench::collision
