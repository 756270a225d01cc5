// SPDX-License-Identifier: MIT
#pragma once

#include "geometry/tet_mesh.h"
#include "models/material.h"
#include "models/model_registry.h"
#include "models/soft_body.h"

#include <memory>

namespace softbench {

// The converged reference: hyperelastic tetrahedral FEM with the stable neo-Hookean energy
// (Smith, de Goes & Kim 2018; stable_neo_hookean.h states the energy and the Lame
// reparametrisation that matches the material's E and nu at small strain), lumped masses, and
// backward Euler solved to convergence by Newton's method. Slow on purpose: it is what the other
// models' accuracy is measured against, not a model for a frame budget.
//
// Step (dt; state x_n, v_n; lumped mass M): x_{n+1} minimises the incremental potential
//     E(x) = 1/(2 dt^2) |x - x_n - dt v_n|_M^2 + alpha/(2 dt) |x - x_n|_M^2 + sum_e V_e Psi(F_e)
//            - (M g + f_ext) . x + sum_penalty k/2 |x_c - target_c|^2,
// whose stationarity is backward Euler with Rayleigh mass damping -alpha M v; then
// v_{n+1} = (x_{n+1} - x_n) / dt. Exact constraints fix x_c = target_c (the unknowns are the free
// vertices only: their rows and columns are eliminated, like corotational_fem's).
//
// Newton: from x = x_n + dt v_n (targets at exact vertices), each iteration assembles the
// gradient and the Hessian (M/dt^2 + alpha M/dt + K + penalty k I); solves it with CHOLMOD
// (symbolic analysis once, at construction; one numeric factorisation per iteration); and
// backtracks along the step until E decreases enough (Armijo). Definiteness fix: every
// element's d^2Psi/dF^2 projected to positive semi-definite (negative eigenvalues of the 9x9
// matrix clamped to zero, stable_neo_hookean.h), which makes the system positive definite and
// the step a descent direction; with `projection` "fallback" (default) only once CHOLMOD has
// found the exact Hessian not positive definite in this step, since the projection costs Newton
// its quadratic convergence. Newton stops when a step's largest vertex displacement is below
// `tolerance` times the rest bounding-box diagonal (that last step is taken in full: what
// remains after it is far smaller).
//
// StepStats: iterations = Newton iterations; factorizations = linear_solves = one per iteration
// (two in the iteration where "fallback" switches to the projection); residual = the last Newton
// step's largest vertex displacement divided by the bounding-box diagonal. A step that did not
// converge (max_iterations reached, or the line search found no decrease) ends with residual >
// tolerance: it is reported, never hidden. finite = false if NaN/Inf appeared or a
// factorisation failed.
//
// Constraint forces: at exact vertices, the gradient of E at the final positions (inertia,
// damping, elastic and external terms: the force the constraint had to exert); at penalty
// vertices, k (target - x).
//
// Cost, measured on the shipped liver (1215 vertices, 4777 tets; scenes/liver_gravity.json: dt
// 1/60 s, gravity, 85 pinned vertices; 2-core machine shared with other jobs): 3.5 Newton
// iterations per step, all with the exact Hessian (the system stayed definite), ~30 ms each
// (CHOLMOD's factorisation ~15-20 ms, the element pass ~8 ms): ~110 ms per step, ~60x
// corotational_fem's default. How converged in dt (max / RMS vertex distance at t = 1 s between
// runs at dt and dt/2, the liver having moved 11 cm RMS): 1/60: 28 / 10 mm, 1/120: 27 / 9.5 mm,
// 1/240: 18 / 6.3 mm, 1/480: 9.1 / 3.5 mm. First-order behaviour (halving the difference) only
// sets in below ~1/240 s: at the scenes' 1/60 s backward Euler's numerical damping of this
// undamped sag is far from converged, so a reference for an undamped scene needs dt <= 1/480 s
// (sweep --reference-substeps 8). The harness's default reference runs at dt/4
// (harness/run/reference.h): the shipped press and pull scenes damp the sag (rayleigh_mass
// 5 /s), which that default relies on; it is not converged for an undamped scene.

struct NeoHookeanParams {
  enum class Projection { kAlways, kFallback };

  /// Definiteness fix. "always": every element's d^2Psi/dF^2 projected to PSD in every Newton
  /// iteration (robust; but the projection drops the negative curvature of compressed and
  /// rotated elements, so Newton converges only linearly near the solution). "fallback": the
  /// exact Hessian while the whole system (with M / dt^2) is positive definite, which CHOLMOD's
  /// factorisation tells, and the projected one for the rest of the step once it is not
  /// (quadratic convergence where possible; a failed factorisation costs one more).
  Projection projection = Projection::kFallback;
  /// Newton stops when its step's largest vertex displacement is below tolerance times the rest
  /// bounding-box diagonal (dimensionless). Smaller: closer to the exact backward Euler step,
  /// more iterations (each a factorisation); quadratic convergence makes one more iteration
  /// typically gain several digits.
  double tolerance = 1e-8;
  /// The most Newton iterations per step; a step that needs more is reported (residual >
  /// tolerance) and continues from where Newton stopped.
  int max_iterations = 50;
  /// Armijo constant c: a step length s is accepted when E(x + s dx) <= E(x) + c s grad E . dx.
  /// Larger: stricter, more backtracking.
  double armijo = 1e-4;
  /// Backtracking factor: a rejected step length is multiplied by this.
  double backtrack = 0.5;
  /// The most step-length reductions per iteration; after that the step is reported as not
  /// converged (the line search found no decrease, e.g. at round-off level).
  int max_backtracks = 30;
  /// 1/s, Rayleigh mass damping alpha: a drag -alpha M v on every vertex. More: slower, less
  /// oscillating motion. 0: undamped (backward Euler still dissipates numerically).
  double rayleigh_mass = 0.0;
};

/// The registry entry ("neo_hookean") with the parameter table.
ModelInfo neo_hookean_info();

/// Direct construction, for tests. Throws InputError on invalid parameters or material.
std::unique_ptr<SoftBody> make_neo_hookean(const TetMesh& mesh,
                                           const Material& material,
                                           const NeoHookeanParams& params);

}  // namespace softbench
