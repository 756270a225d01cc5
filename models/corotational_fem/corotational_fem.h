// SPDX-License-Identifier: MIT
#pragma once

#include "geometry/tet_mesh.h"
#include "models/material.h"
#include "models/model_registry.h"
#include "models/soft_body.h"

#include <memory>

namespace softbench {

// Corotational linear FEM on the tets of the mesh (warped stiffness: Mueller & Gross 2004,
// "Interactive virtual materials"), or plain linear FEM, with lumped masses and Rayleigh damping,
// integrated by backward Euler linearised once per step.
//
// Elements: linear tets. Node a of a tet with rest volume V and shape-function gradient b_a
// (1/m) gets the elastic force f_a = -V R sigma(sym(R^T F) - I) b_a, with F the deformation
// gradient, sigma(eps) = 2 mu eps + lambda tr(eps) I (Lame parameters of the material) and R the
// element's rotation: the polar rotation of F ("corotational"; robust for inverted and
// degenerate elements, see polar_decomposition.h) or I ("linear", which is not invariant under
// rotation: a rigidly rotated body feels spurious forces). Elastic energy
// sum V [mu |S - I|^2 + lambda/2 tr(S - I)^2], S = sym(R^T F) (corotational: the stretch of F).
//
// Sign conventions: f is the force the element exerts on its nodes (N, world axes); the stiffness
// K = -df/dx (R held fixed, the standard warped-stiffness tangent) is symmetric positive
// semi-definite, assembled from the blocks K_ab = V [lambda c_a c_b^T + mu c_b c_a^T +
// mu (c_a . c_b) I], c = R b.
//
// Step (dt, state x, v; lumped mass M; Rayleigh damping C = alpha M + beta K): backward Euler
// M dv = dt [f(x + dt (v + dv)) - C (v + dv) + f_ext] with f linearised once at x
// (f(x + d) = f(x) - K d), i.e.
//     (M + dt C + dt^2 K) dv = dt (f(x) + f_ext) - dt (alpha M + (beta + dt) K) v,
// then v += dv, x += dt v. f_ext is gravity M g, the step's external forces and penalty springs
// (k (target - x), adding dt^2 k I to the matrix and -dt^2 k v to the right-hand side). The
// system is symmetric positive definite; one linear solve per step. For corotational elements
// the right-hand side's element part is -dt V R sigma(sym(R^T (F + (beta + dt) G)) - I) b_a, G
// the velocity gradient, so K v costs no extra product.
//
// Exact constraints are eliminated: the constrained vertex ends the step on its target with
// v = (target - x) / dt, and its reaction is (A dv - b)_c / dt from its rows as assembled.
// StepStats.residual: |A dv - b| / |b| of the constraint-eliminated system (CG: its recursively
// updated residual); iterations: CG iterations (0 for CHOLMOD); factorizations: numeric
// Cholesky factorisations this step.
//
// Threads: from 2048 vertices (the shipped liver has 1215: one thread) OpenMP over elements,
// vertices, edges, CG chunks and the SSOR sweeps' two parts, every sum in a fixed order: results
// are bit-identical for any thread count. Each step runs on the threads or on one, whichever has
// lately been faster (CorotationalFemModel::kThreadedVertices says why).
//
// Defaults: the fastest settings that match CHOLMOD within 1% on the shipped liver, measured
// with bench/fem_bench.cpp (1215 vertices, 4777 tets, E 3000 Pa, nu 0.3, dt = 1/60 s, pinned at
// the lowest 10% of x and sagging under gravity; one core) and on the liver scenes against
// solver "cholmod": CG preconditioned by symmetric block Gauss-Seidel (models/ssor_solver.h),
// started from the best combination of the last four velocity changes (models/warm_start.h),
// stopped at an estimated energy-norm error of 1e-3 (6 iterations a step where Jacobi-PCG from
// the last solution took 19; the tool force on liver_press within 0.005% RMS of CHOLMOD's,
// liver_pull 0.0004%), and 3 warm-started quaternion iterations per element (0.15% from the
// SVD's exact rotations; each iteration costs ~0.03 ms per step on the liver, the SVD ~2.9 ms).

struct CorotationalFemParams {
  enum class Formulation { kCorotational, kLinear };
  enum class Rotation { kSvd, kQuaternion };
  enum class LinearSolver { kCholmod, kConjugateGradient, kCholeskyPcg };

  /// "corotational": rotation-invariant, right under large rotations; "linear": plain linear
  /// FEM (R = I), cheaper (no rotations) but a rotated body feels spurious forces.
  Formulation formulation = Formulation::kCorotational;
  /// Corotational only. "svd": JacobiSVD with Irving et al. 2004's sign fix; exact and robust,
  /// ~0.5 us per element. "quaternion": Mueller et al. 2016, warm-started from the previous
  /// step's rotation; ~0.05 us per iteration per element, exact once converged.
  Rotation rotation = Rotation::kQuaternion;
  /// Quaternion only: the most iterations per element and step. More: closer to the exact
  /// rotation under fast rotation, slower. Warm-started, each iteration removes about 2/3 of the
  /// lag behind a rotating element (liver sag after 1 s vs SVD: 1.9% with 1, 0.4% with 2, 0.15%
  /// with 3).
  int rotation_iterations = 3;
  /// Quaternion only, rad: elements stop iterating (in batches of 8) once their next updates
  /// would all be smaller.
  double rotation_tolerance = 1e-6;
  /// 1/s, Rayleigh mass damping alpha (C = alpha M + beta K): drag on every vertex's velocity.
  /// More: slower, less oscillating motion.
  double rayleigh_mass = 0.0;
  /// s, Rayleigh stiffness damping beta: damps deformation rates, the faster modes more. More:
  /// quicker settling, and more CG iterations (the system's stiff part grows by (beta + dt)/dt).
  double rayleigh_stiffness = 0.0;
  /// "cholmod": exact, a numeric factorisation every step (liver: ~20 ms, ~12x "cg"); "cg":
  /// warm-started Jacobi-PCG to cg_tolerance (fastest); "cholesky_pcg": PCG preconditioned by a
  /// Cholesky factor kept across steps and refactorised when a solve needs more than
  /// refresh_iterations (few iterations while the matrix changes slowly, each costly).
  LinearSolver solver = LinearSolver::kConjugateGradient;
  enum class Preconditioner { kJacobi, kSsor };
  /// "cg" only. "ssor": symmetric block Gauss-Seidel (models/ssor_solver.h), few iterations,
  /// its sweeps on two parts of the mesh side by side from 2048 vertices; "jacobi": the
  /// inverse diagonal, twice the iterations and 3x the error at the same tolerance, parallel
  /// over vertices from 2048 (bench/fem_bench.cpp compares them).
  Preconditioner preconditioner = Preconditioner::kSsor;
  /// "ssor" only: vertices per aggregate of the two-level solve's coarse space (each aggregate's
  /// three translations solved exactly, models/coarse_space.h); at least the vertex count: the
  /// whole body one aggregate; 0: chosen by the mesh's size (CorotationalFemModel::
  /// kCoarseFromVertices). Smaller aggregates: fewer iterations on large meshes, a larger coarse
  /// system to factorise each step.
  int coarse_vertices = 0;
  enum class SweepPrecision { kAuto, kDouble, kSingle };
  /// "ssor" only: the precision of the matrix the sweeps read (LinearSolverOptions::
  /// single_precision_sweeps). "single" halves the bytes an iteration, which is what bounds the
  /// sweeps once the matrix outgrows the cache; "auto": single from CorotationalFemModel::
  /// kSingleSweepsFromVertices, where it was measured faster. Either way the doubles are read
  /// below a cg_tolerance of 1e-6 (SsorConjugateGradientSolver::kSingleSweepsTolerance), which
  /// the rounded sweeps cannot reach.
  SweepPrecision sweep_precision = SweepPrecision::kAuto;
  /// Iterative solvers: start each solve from the best combination (in the energy norm) of the
  /// last step's velocity change and the three before it (models/warm_start.h; their four
  /// products in one pass over the matrix a step) instead of the last one alone.
  bool projected_warm_start = true;
  /// Iterative solvers: stop once the estimated energy-norm error of the new velocity is below
  /// cg_tolerance times its energy norm (LinearSolverOptions::tolerance): the error that matters,
  /// whatever dominates the right-hand side. Measured against CHOLMOD on liver_press: 1e-2 ->
  /// 11 iterations, peak force within 0.2% but a contact released a step late (7% RMS over the
  /// force curve); 1e-3 -> 19 iterations, 0.03% peak and 0.01% RMS; 1e-4 -> 29. On a sphere
  /// pressed into a soft block (E 5 kPa, nu 0.45) the old |r| <= 1e-2 |b| rule stopped after
  /// 0.7 iterations a step and the block inverted; this one follows CHOLMOD's force.
  double cg_tolerance = 1e-3;
  /// Iterative solvers: cap per step; a step that hits it reports iterations == cap.
  int cg_max_iterations = 500;
  /// "cholesky_pcg": refactorise before the next step when a solve needed more iterations than
  /// this. Smaller: more factorisations, fewer iterations.
  int refresh_iterations = 8;
};

/// The registry entry ("corotational_fem") with the parameter table.
ModelInfo corotational_fem_info();

/// Direct construction, for tests. Throws InputError on invalid parameters or material.
std::unique_ptr<SoftBody> make_corotational_fem(const TetMesh& mesh,
                                                const Material& material,
                                                const CorotationalFemParams& params);

}  // namespace softbench
