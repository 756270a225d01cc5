// SPDX-License-Identifier: MIT
#pragma once

// Guigue and Devillers' triangle-triangle test (P. Guigue, O. Devillers, "Fast and robust
// triangle-triangle overlap test using orientation predicates", JGT 8(1), 2003), the second peer:
// only signs of orient3d determinants. Each triangle's vertices are classified against the
// other's plane, a circular permutation makes p1 (resp. p2) the vertex alone on its side, and two
// more orient3d decide whether the intervals on the intersection line overlap. Coplanar pairs go
// to a 2D test with orient2d on the dominant projection (here a direct edge-crossing plus
// containment test with the same predicates, not the paper's 2D decision tree).
//
// Plain double determinants, as the peers are measured (shared/notes/collision.md): exact on
// generic input, wrong on part of the shared-vertex and shared-edge pairs where rounding decides;
// degenerate triangles are outside its contract. The segment, when asked for, is built after the
// decision from the plane distances on the canonical edges (as the paper's construct variant
// does with its alpha ratios).

#include "collision/tri_tri_result.h"

#include <Eigen/Core>

namespace softbench::collision {

TriTriResult tri_tri_guigue(const Eigen::Vector3d& p0,
                            const Eigen::Vector3d& p1,
                            const Eigen::Vector3d& p2,
                            const Eigen::Vector3d& q0,
                            const Eigen::Vector3d& q1,
                            const Eigen::Vector3d& q2);

}  // namespace softbench::collision
