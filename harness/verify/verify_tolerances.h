// SPDX-License-Identifier: MIT
// The tolerances of `softbench verify`, each with the reason for its value: the one place they
// are stated (the reports print them beside each value).
#pragma once

#include "harness/run/metrics.h"

namespace softbench::harness::verify_tolerance {

/// patch: largest interior distance from the affine field / largest imposed displacement. A
/// linear tet reproduces a uniform strain exactly, so a consistent element leaves only the
/// settling and the solver's stopping error (3e-7 measured with the default CG); 1e-3 admits an
/// iterative solver's stop while a force law that is not consistent for uniform strain misses
/// it by far (shape matching's cluster goals: 0.21, bullet_softbody's links: 0.58).
inline constexpr double kPatch = 1e-3;

/// rigid_motion: largest vertex distance from the rotated and translated rest shape / bbox
/// diagonal over the free steps. A rotation-invariant force law sees no strain and does not
/// move (1e-16 measured); one that is not (plain linear FEM) is pulled toward the unrotated
/// shape (the tests check it misses by 100x and more). 1e-4 admits a rotation found iteratively
/// and converging over the first steps.
inline constexpr double kRigidDisplacement = 1e-4;
/// rigid_motion: elastic energy after the free steps / (E x volume), for a model with one: the
/// strain energy density of a 1e-4 strain is 1e-8 E, so 1e-8 is the energy of a deformation at
/// the displacement tolerance.
inline constexpr double kRigidEnergy = 1e-8;

/// cantilever: |tip deflection / Euler-Bernoulli's - 1| at the finest level. Linear tets are
/// too stiff in bending (shear locking): the error falls with the mesh, but slowly (the
/// corotational FEM and bullet_deformable: 0.78, 0.49, 0.21 at 1, 2, 4 cells across the side);
/// the 3D beam also differs from Euler-Bernoulli by shear (~1% at L/h = 10) and its clamped
/// face. 0.25 is what a consistent linear-tet element reaches at 4 cells across; a finer level
/// (8 cells, 31k tets) would take 10 s and more per model.
inline constexpr double kCantilever = 0.25;

/// hertz: |force / Hertz's - 1| at the deepest point. Hertz's solution is for a half-space and
/// a paraboloid (small contact radius against R); at 0.3 R the sphere's own shape, the finite
/// block, the margin the contact keeps and the discrete contact over a few elements each take
/// a few percent.
inline constexpr double kHertz = 0.15;
/// hertz: the largest change of the force over a hold / the force. A quasi-static press whose
/// contact neither creeps nor sticks holds its force: 2%.
inline constexpr double kHertzHoldDrift = 0.02;
/// hertz: the largest fall of the force from one step to the next while the sphere goes down
/// or holds / the deepest force. The force grows with depth; a contact that lets go and takes
/// hold again shows as a fall (a vertex at the patch's rim taken and let go on alternate steps:
/// 1% measured). 2%, as for the hold.
inline constexpr double kHertzDrop = 0.02;

/// free_spin: |L(t) - L(0)| / |L(0)| over 2 s, and the shape's RMS distance from its rigid fit
/// / bbox diagonal: 1% each (the free-spin acceptance bounds). Backward Euler and position
/// projection lose L at first order in dt (about 20% at 1/60 s): they fail the momentum bound
/// at the scenes' step, which is what the case is there to show.
inline constexpr double kSpinMomentum = 0.01;
inline constexpr double kSpinShape = 0.01;

/// squash_release: the recovery residual at the end, as every report judges recovery.
inline constexpr double kSquashResidual = kRecoveredResidual;

}  // namespace softbench::harness::verify_tolerance
