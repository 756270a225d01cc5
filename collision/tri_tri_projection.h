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
// Exactness: every sign decision equals the exact one for every finite input. The common case
// is decided in floating point with a priori error bounds (collision/tri_tri_projection_bounds.h:
// the z* signs, the V and W rejections, the clipping signs e_i and the order of the chord and
// L_B on the line); whatever those cannot certify is decided by filtered exact predicates
// (collision/exact_predicates.h):
//  - the side of H each Q_i lies on is orient3d(P1, P2, P0, Q_i);
//  - the characteristic values e_i of the clipping (P_i in the line equation of L_B) are, up to
//    a positive factor, orient3d(Q0, Q1, Q2, P_i), because L_B is the trace of B's plane in H;
//  - the overlap of two collinear segments (figure 4.15) compares points of the line
//    H x B-plane; a point on A's edge PaPb against one on B's edge QcQd is ordered by
//    orient3d(Pa, Pb, Qc, Qd);
//  - in-plane tests (cases (a), (c)) use orient2d on the projection that drops the dominant
//    coordinate of A's normal (exact, the points being exactly coplanar).
// The frame is not normalised: the thesis's unit axes become x* = P1P2, z* = N and y* = N x x*,
// the same directions with other lengths, which leave every sign and every comparison of ratios
// unchanged (t = |z1| / (|z1| + |z0|) is compared multiplied through by its denominator), so
// no square root or division is needed for a decision.
//
// Degenerate (zero-area, collinear) triangles are reduced exactly to the segment or point they
// are and tested exactly: a crossing or touching gives kSegment with the common point (or the
// collinear overlap of two segments), a segment lying in the other (proper) triangle's plane
// and meeting it gives kCoplanar, a point touching anything gives kSegment of length zero.
// Identical or reversed triangles are kCoplanar. For kSegment, [a, b] is B intersected with A.

#include "collision/tri_tri_result.h"

namespace softbench::collision {

TriTriTest tri_tri_projection;

}  // namespace softbench::collision
