// SPDX-License-Identifier: MIT
#pragma once

#include "geometry/tet_mesh.h"
#include "models/material.h"
#include "models/model_registry.h"
#include "models/soft_body.h"

#include <memory>

namespace softbench {

// Projective Dynamics (Bouaziz, Martin, Liu, Kavan, Pauly 2014, "Projective Dynamics: fusing
// constraint projections for fast simulation", SIGGRAPH): backward Euler on lumped masses,
// solved by alternating a local step (per element, the nearest point on a constraint manifold)
// and a global step (one linear solve whose matrix never changes, factored once by CHOLMOD).
//
// The elastic energy is the corotated one corotational_fem uses, written as two PD constraints
// per tet (F its deformation gradient, R the nearest rotation, V its volume, mu and lambda the
// material's Lame parameters):
//     w_s/2 |F - R|^2                 w_s = 2 mu V       (as-rigid-as-possible)
//     w_v/2 |F - (F - c R)|^2         w_v = 3 lambda V,  c = (tr(R^T F) - 3) / 3
// The second projection, F - c R = U (Sigma - c I) V^T, is the nearest matrix whose singular
// values sum to 3, so its energy is w_v/2 * 3 c^2 = lambda V/2 tr(R^T F - I)^2. Together:
// V [mu |S - I|^2 + lambda/2 tr(S - I)^2] with S = R^T F, corotational_fem's element energy
// exactly (not only at small strain). So the converged PD step is the exact backward Euler step
// of corotational_fem's material, where corotational_fem takes one linearised solve per step.
//
// Step (dt; x_n, v_n; M lumped; alpha = rayleigh_mass): x minimises
//     1/(2 dt^2) |x - y|_M^2 + alpha/(2 dt) |x - x_n|_M^2 + sum of the constraints' energies,
//     y = x_n + dt v_n + dt^2 (g + M^-1 f_ext),
// from x = y. Each iteration: local (per tet F, R by Mueller et al.'s warm-started rotation
// extraction, and the projections' right-hand side), then global (A x = b, A = M (1/dt^2 +
// alpha/dt) + sum (w_s + w_v) G^T G, the same scalar matrix for x, y and z: one factor, three
// right-hand sides at once). v = (x - x_n) / dt at the end.
//
// Holds (PositionConstraint), two ways, so that contact never refactors:
// - an exact full hold that anchors (the fixed region, a grasp) is eliminated from A: its row
//   and column become the identity's and its target moves to the right-hand side. The factor is
//   recomputed only when that set of vertices (or dt) changes: at construction, at a grasp and
//   at its release.
// - every other hold (contact, a sliding support, a penalty spring) is imposed on the kept
//   factor by Lagrange multipliers (held_rows.h): each held direction is a row, its column of
//   A^-1 is computed once while the factor lasts, and a small dense system (rows x rows) gives
//   the multipliers, which are the hold's forces. A penalty hold adds its compliance 1/k to that
//   system's diagonal (the same as adding k to A, by Woodbury's identity).
//
// StepStats: iterations = local/global iterations; residual = the last iteration's largest
// vertex move divided by the rest bounding-box diagonal; factorizations = numeric CHOLMOD
// factorisations (0 in most steps); linear_solves = global solves plus the multiplier columns
// computed; truncated_solves = 1 when `tolerance` > 0 and the iterations ran out before it.
struct ProjectiveDynamicsParams {
  /// Local/global iterations per step (the speed knob): more, closer to the exact backward
  /// Euler step of the corotated energy; each costs one pass over the tets and three triangular
  /// solve pairs.
  int iterations = 10;
  /// Stop early when an iteration moves no vertex by more than tolerance x the rest
  /// bounding-box diagonal; 0: always run `iterations`.
  double tolerance = 0.0;
  /// 1/s, Rayleigh mass damping: a drag -alpha M v on every vertex (0: only backward Euler's
  /// numerical damping).
  double rayleigh_mass = 0.0;
  /// Chebyshev semi-iterative acceleration (Wang 2015, "A Chebyshev semi-iterative approach
  /// for accelerating projective and position-based dynamics"): the estimated spectral radius
  /// rho of the plain iteration, in [0, 1); 0 turns it off.
  double chebyshev_rho = 0.8;
  /// Plain iterations before the acceleration starts.
  int chebyshev_delay = 2;
  /// Rotation-extraction updates per element per iteration (warm-started from the last).
  int rotation_iterations = 2;
};

namespace projective_dynamics {
/// The local step runs on one thread below this many tets (as corotational_fem's element
/// loops): there an OpenMP barrier costs more than the split saves on a shared 2-core machine.
constexpr int kParallelElements = 16384;
}  // namespace projective_dynamics

/// The registry entry ("projective_dynamics") with the parameter table.
ModelInfo projective_dynamics_info();

/// Direct construction, for tests. Throws InputError on invalid parameters or material.
std::unique_ptr<SoftBody> make_projective_dynamics(const TetMesh& mesh,
                                                   const Material& material,
                                                   const ProjectiveDynamicsParams& params);

}  // namespace softbench
