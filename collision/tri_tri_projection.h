// SPDX-License-Identifier: MIT
#pragma once

// The thesis's triangle-triangle test (section 4.4.2, after Yu Haiyan et al.): projection onto a
// computation frame built on triangle A, with exact signs.
//
// Frame: origin P1, x* along P1P2, z* along A's normal (P1P2 x P1P0), y* = z* x x*. H is the
// x*y* plane (A's plane), V the y*z* plane, W the x*z* plane. B's vertices are classified by
// the side of H they lie on into the six cases of figure 4.14, relabelled so that Q0 is the
// special vertex; L_B = B intersected with H (ends Q_L, Q_R, by t = |z1| / (|z1| + |z0|)) is
// rejected early on V, then on W; what survives is decided in H by the convex-polygon line
// clipping of figure 4.16, and coplanar triangles by clipping B's edges plus the containment
// test of figure 4.17.
//
// Exactness: every sign decision is a filtered exact predicate on the input coordinates
// (collision/exact_predicates.h), so the answer equals the exact one for every input:
//  - the side of H each Q_i lies on is orient3d(P1, P2, P0, Q_i);
//  - the characteristic values e_i of the clipping (P_i in the line equation of L_B) are, up to
//    a positive factor, orient3d(Q0, Q1, Q2, P_i), because L_B is the trace of B's plane in H;
//  - the overlap of two collinear segments (figure 4.15) compares points of the line
//    H x B-plane; a point on A's edge PaPb against one on B's edge QcQd is ordered by
//    orient3d(Pa, Pb, Qc, Qd);
//  - in-plane tests (cases (a), (c)) use orient2d on the projection that drops the dominant
//    coordinate of A's normal (exact, the points being exactly coplanar).
// The V and W rejections use the frame coordinates in floating point but reject only with a
// margin larger than the frame's rounding error, so they never reject touching triangles.
// Segment end points are floating point (world frame).
//
// Tolerance policy (closed sets, no epsilon): touching at a vertex or along an edge intersects;
// an edge lying in the other's plane is a segment contact; identical or reversed triangles are
// kCoplanar. Degenerate (zero-area, collinear) triangles are reduced exactly to the segment or
// point they are and tested exactly: a crossing or touching gives kSegment with the common point
// (or the collinear overlap of two segments), a segment lying in the other (proper) triangle's
// plane and meeting it gives kCoplanar, a point touching anything gives kSegment of length zero.

#include "collision/tri_tri_result.h"

#include <Eigen/Core>

namespace softbench::collision {

/// Intersection of triangle A = (p0, p1, p2) and triangle B = (q0, q1, q2), exact for finite
/// input (see above). For kSegment, [a, b] is B intersected with A (a == b for a point contact).
TriTriResult tri_tri_projection(const Eigen::Vector3d& p0,
                                const Eigen::Vector3d& p1,
                                const Eigen::Vector3d& p2,
                                const Eigen::Vector3d& q0,
                                const Eigen::Vector3d& q1,
                                const Eigen::Vector3d& q2);

}  // namespace softbench::collision
