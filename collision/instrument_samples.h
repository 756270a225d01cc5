// SPDX-License-Identifier: MIT
// The points of a rigid instrument's surface the contact tests against the tissue: an instrument
// point inside the tissue pushes the tissue triangle over it out (collision/instrument_contact.h).
// They must be close enough that no tissue triangle passes between them, and no closer: every
// point costs a nearest-point search each contact pass it is near the tissue.
#pragma once

#include "geometry/tri_mesh.h"

#include <Eigen/Core>

namespace softbench::collision {

/// Points on `mesh`'s surface (its own frame): every vertex of the mesh, and points of a grid of
/// step spacing / 4 on each triangle where no point already taken is nearer than
/// kSampleSeparation * spacing, the grid's points on the sharpest edges first (the angle between
/// their faces), then on the other edges, then inside the faces. Every point of the surface is
/// then within spacing / sqrt(3) of one, as with a plain grid of step `spacing` on each triangle,
/// which took a long thin triangle's short side as finely as its long one, and every side of
/// every triangle apart: on the 6 mm probe (1,248 triangles, rings of 24 vertices) beside the
/// liver's 4.8 mm spacing it made 4,226 points, 900 now, each searched for its nearest tissue
/// triangle where the tissue is near. Throws InputError if the grid would hold more than
/// kMaxSampleCandidates points (a mesh in other units than the tissue's), before allocating.
Eigen::Matrix3Xd instrument_samples(const TriMesh& mesh, double spacing);

/// The separation, in spacings: a grid point nearer than it to a point already taken is not
/// taken. Each surface point is within spacing / (4 sqrt(3)) of a grid point (the grid's triangles
/// have sides of at most spacing / 4), which is within this of a sample, so within spacing /
/// sqrt(3).
inline constexpr double kSampleSeparation = 0.75 / 1.7320508075688772;

/// The most grid points instrument_samples() visits before thinning (each costs 27 hash
/// lookups, about half a microsecond: 2 million, one second, and at most as many points kept,
/// 48 MB): a tool that needs more is far larger than the tissue's edges.
inline constexpr double kMaxSampleCandidates = 2'000'000;

}  // namespace softbench::collision
