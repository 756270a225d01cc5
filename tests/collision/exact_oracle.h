// SPDX-License-Identifier: MIT
#pragma once

// The exact oracle for the triangle-triangle tests (tests only): CGAL's do_intersect on
// Triangle_3 with the Exact_predicates_inexact_constructions kernel, whose predicates are exact
// for double input. Degenerate (collinear) triangles, which CGAL's Triangle_3 test excludes by
// precondition, are reduced exactly to the segment or point they span and tested with the
// Segment_3 / Point_3 overloads.

#include "collision/tri_tri_result.h"

#include <Eigen/Core>

namespace softbench::collision::test {

/// Exact answer, with the contact kind of the documented policy (collision/tri_tri_result.h,
/// collision/tri_tri_projection.h): kCoplanar when both are proper triangles in one plane, or one
/// is a segment-like degenerate triangle lying in the plane of the other, proper one; kSegment for
/// every other contact (including a point-like degenerate triangle touching anything).
TrianglePairFunction<TriTriContact> exact_contact;

/// exact_contact(...) != kDisjoint, without classifying the contact (what the benchmark times as
/// "CGAL's exact test": two collinearity checks, then Triangle_3 do_intersect).
TrianglePairFunction<bool> exact_intersect;

/// Exactly collinear (zero-area) triangle.
bool exactly_degenerate(const Eigen::Vector3d& p0,
                        const Eigen::Vector3d& p1,
                        const Eigen::Vector3d& p2);

/// Squared distance from x to the closed proper triangle (p0, p1, p2), in double (CGAL Epick
/// construction; for checking segment end points within a tolerance).
double squared_distance_to_triangle(const Eigen::Vector3d& x,
                                    const Eigen::Vector3d& p0,
                                    const Eigen::Vector3d& p1,
                                    const Eigen::Vector3d& p2);

}  // namespace softbench::collision::test
