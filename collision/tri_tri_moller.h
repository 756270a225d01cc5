// SPDX-License-Identifier: MIT
#pragma once

// Moeller's interval-overlap triangle-triangle test (T. Moeller, "A fast triangle-triangle
// intersection test", JGT 2(2), 1997), the peer of the projection method: signed distances of
// each triangle's vertices to the other's plane, then the two intervals where the triangles cut
// the line L = N1 x N2, projected on L's dominant axis; coplanar triangles by 2D edge tests and
// point-in-triangle on the dominant projection.
//
// Plain double, no EPSILON snap: the paper's absolute 1e-6 snap of the plane distances is
// scale-dependent (false positives for near-parallel and small triangles, see
// shared/notes/collision.md section 0.4), so it is left out. Without it the test is exact on
// generic input but not on shared vertices and edges, where rounding decides. Degenerate
// triangles are outside its contract (their zero normal sends them to the coplanar branch).
// The segment is the overlap of the two intervals, as in the paper's tri_tri_intersect_with_
// isectline variant.

#include "collision/tri_tri_result.h"

#include <Eigen/Core>

namespace softbench::collision {

TriTriResult tri_tri_moller(const Eigen::Vector3d& p0,
                            const Eigen::Vector3d& p1,
                            const Eigen::Vector3d& p2,
                            const Eigen::Vector3d& q0,
                            const Eigen::Vector3d& q1,
                            const Eigen::Vector3d& q2);

}  // namespace softbench::collision
