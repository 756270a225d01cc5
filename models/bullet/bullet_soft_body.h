// SPDX-License-Identifier: MIT
#pragma once

#include "geometry/tet_mesh.h"
#include "models/calibration_record.h"
#include "models/material.h"
#include "models/model_registry.h"
#include "models/soft_body.h"

#include <memory>
#include <optional>
#include <string>

namespace softbench {

// Bullet Physics 3.24's soft bodies (double-precision build) as outside baselines: what a user
// would otherwise pick. Two registered models share one adapter (models/bullet/bullet_body.h):
//
// - "bullet_softbody": the classic btSoftBody in a btSoftRigidDynamicsWorld, a position-based
//   solver (Mueller et al. 2007, "Position based dynamics"): one link per unique tet edge
//   projected `position_iterations` times per step with stiffness kLST, optional global shape
//   matching (kMT, Mueller et al. 2005), surface volume conservation (kVC) and k-means clusters.
//   Its stiffness has NO physical unit: the sag it gives depends on dt, the iteration count and
//   the mesh. Use `softbench calibrate SCENE --model bullet_softbody` to fit `stiffness` so its
//   static sag under gravity matches the corotational FEM at the scene's dt, and keep the
//   printed "calibrated" record in the block so reports show the run as calibrated.
// - "bullet_deformable": btDeformableMultiBodyDynamicsWorld (Han et al., Bullet's deformable
//   solver, PR 2351) with one elastic force built from the scene's material: Bullet's stable
//   neo-Hookean (Smith et al. 2018, "Stable neo-Hookean flesh simulation"), its corotated
//   force, or its mass-spring force, plus gravity; backward Euler linearised newton_iterations
//   times per step (implicit) or symplectic Euler with implicit damping (explicit), with
//   Bullet's conjugate gradient and its mass preconditioner. Projection is always on: Bullet's
//   default Krylov path (conjugate residual with Lagrange multipliers) gives exactly zero motion
//   under the implicit scheme in 3.24. The implicit solve starts from dv = 0 (Bullet keeps its
//   explicit predictor only for nodes in contact), so a step is as accurate as the CG tolerance
//   (free fall: 2e-5 relative at the default). Matched material: Bullet's stable neo-Hookean
//   given the scene's mu and lambda as they are linearises to mu_eff = 3/4 mu (its log term),
//   a material ~27% softer in E at nu = 0.3; lame_mapping "matched" (the default) passes Smith
//   et al.'s reparametrisation instead, and a clamped bar then sags like the corotational FEM's
//   (2% apart at small strain, bullet_test.cpp). The corotated force has no Hessian in 3.24: with
//   implicit true its force enters the residual but not the matrix, which blows up at any dt;
//   with implicit false it needs dt below the CFL limit (~1 ms on the liver).
//
// Shared by both: Bullet's node i is the mesh's vertex i, tets are appended as the mesh orders
// them (positive volume), links are the unique edges, node masses are the lumped masses of the
// material density. Units SI. Bullet's own collision detection is off (m_cfg.collisions = 0):
// contacts reach the model, like pins and grasps, as PositionConstraints.
//
// Constraints, and what Bullet honours exactly:
// - exact (stiffness kExact): the node's mass is set to 0 (Bullet's kinematic node: no solver
//   moves it) and its velocity to (target - x) / dt, so Bullet's own integration takes it to the
//   target; the adapter then writes the target itself, removing round-off. Exact: the step
//   reports max_constraint_error 0. A node whose constraint disappears (grasp release) gets its
//   lumped mass back. StepStats.residual is the largest distance Bullet itself left an exactly
//   constrained node from its target before that write, m: round-off for bullet_deformable;
//   for bullet_softbody ~5e-8 of the node's travel in the step (1e-9 m for 1.3 cm), since
//   btSoftRigidDynamicsWorld hands dt to the soft body as a float even in the double build.
// - penalty (finite stiffness k, N/m): a force k (target - x) on the node; bullet_softbody
//   applies it explicitly (btSoftBody::addForce), bullet_deformable implicitly (a Lagrangian
//   force with Hessian -k I, typed as Bullet's mouse-picking spring so it is implicit in both
//   schemes). Approximate: max_constraint_error is the largest |x - target| after the step.
// - StepInput::external_forces: btSoftBody::addForce (softbody) or a constant Lagrangian force
//   (deformable).
//
// StepStats: iterations = the position iterations (softbody) or the conjugate-gradient
// iterations of the step (deformable; Bullet caps them at cg_max_iterations per solve);
// linear_solves = Krylov solves (deformable, one per Newton iteration); finite = false as soon
// as a position or velocity is NaN/Inf, after which step() no longer calls Bullet.
// constraint_forces() is an ESTIMATE (Bullet reports no reaction for zero-mass nodes): per
// constrained node m_i (v_new - v_old) / dt - f_external - f_internal, with the internal forces
// from Bullet's own force objects at the end of the step (deformable); the softbody solver has no
// forces, so there the body's total reaction from momentum balance is shared among the
// constrained nodes by lumped mass (the sum is right; the split is not). elastic_energy(): NaN
// for bullet_softbody (links have no energy in Bullet); for bullet_deformable the energy of
// Bullet's force evaluated by the adapter from the tets (neo-Hookean relative to the rest state,
// whose energy density Bullet's formula does not zero). reset() rebuilds the Bullet world.

struct BulletSoftBodyParams {
  /// Bullet's link stiffness kLST, in (0, 1], no unit: the fraction of each link's length error
  /// removed per projection. Its effect depends on dt, position_iterations and the mesh (the
  /// same value sags 200x more at dt = 1/60 than at 1 ms); calibrate it against a reference.
  double stiffness = 1.0;
  /// Bullet's m_cfg.piterations: link projections per step. More: stiffer and costlier (the
  /// cost is linear in it); at kLST = 1 the only stiffness knob left.
  int position_iterations = 10;
  /// Bullet's kDP, in [0, 1]: the fraction of every node's velocity removed per step. It
  /// depends on dt (0.01 at 1/60 s is ~0.6 /s); more: faster settling, less rebound.
  double damping = 0.0;
  /// Bullet's kMT, in [0, 1]: each step, every free node moves this fraction toward the
  /// best rigid placement of the rest shape (global shape matching). Resists large deformation
  /// of the whole body, not local detail. Its node weights are set once at construction.
  double pose_matching = 0.0;
  /// Bullet's kVC, >= 0: pressure-like force keeping the closed surface's volume (not per tet).
  /// 0 = off; needs the boundary faces, which are built only when it is on.
  double volume_conservation = 0.0;
  /// k-means clusters (btSoftBody::generateClusters); 0 = none. Each cluster matches its own
  /// rigid frame (local shape matching, strength pose_matching): costlier, stiffer locally.
  int clusters = 0;
  /// Set by `softbench calibrate`; absent (null) when stiffness was not fitted.
  std::optional<CalibrationRecord> calibrated;
};

struct BulletDeformableParams {
  enum class Force { kNeoHookean, kCorotated, kMassSpring };
  enum class LameMapping { kMatched, kDirect };

  /// "neo_hookean" (Bullet's stable neo-Hookean from the scene's E and nu; implicit-capable),
  /// "corotated" (Bullet's corotated linear, E and nu; explicit only in 3.24: no Hessian, no
  /// damping), "mass_spring" (one spring per edge of spring_stiffness; implicit-capable).
  Force force = Force::kNeoHookean;
  /// neo_hookean only. "matched": Bullet gets mu' = 4/3 mu, lambda' = lambda + 5/6 mu (Smith
  /// et al. 2018, section 3.4), so its small-strain response is the scene's E and nu; "direct":
  /// the scene's mu and lambda as they are (what Bullet's demos do), which Bullet's energy turns
  /// into a material ~27% softer in E at nu = 0.3 (mu_eff = 3/4 mu).
  LameMapping lame_mapping = LameMapping::kMatched;
  /// true: backward Euler (stable at large dt, numerically damped, costs CG solves); false:
  /// symplectic Euler for the elastic force, stable only below the CFL limit (~1 ms here).
  bool implicit = true;
  /// s, neo-Hookean only: Bullet's damping stress d mu (dF + dF^T) + d lambda tr(dF) I. More:
  /// faster settling, more CG iterations. Bullet's own default is 0.05. Not rotation-invariant
  /// (dF of a rotated body spinning is not skew): it brakes rigid rotation too, and a free box
  /// spun at 3 rad/s keeps 0.02% of its angular momentum after 2 s (tests/models/
  /// free_spin_test.cpp).
  double damping = 0.05;
  /// N/m per link, mass_spring only; 0 = young_modulus x the mean edge length (the usual k ~ E h
  /// heuristic: 450 N/m for 30 kPa and 1.5 cm edges). Stiffer: smaller sag, smaller stable dt.
  double spring_stiffness = 0.0;
  /// N s/m per link, mass_spring only: dashpot along the link.
  double spring_damping = 0.05;
  /// Bullet's CG stops when r.z < cg_tolerance min(1, b.z0) (z = M^-1 r: roughly the square of
  /// a relative residual, so 1e-8 ~ |r|/|b| 1e-4, the corotational FEM's default). Bullet's own
  /// default in the double build is DBL_EPSILON (2.2e-16), which always runs to the cap.
  double cg_tolerance = 1e-8;
  /// CG iterations per solve (Bullet's kMaxConjugateGradientIterations, 300). Hitting it shows
  /// as iterations == cap x linear_solves.
  int cg_max_iterations = 300;
  /// Implicit only: Newton iterations per step (Bullet's default 1: one linearised solve).
  /// More: closer to the nonlinear backward Euler step, one CG solve each.
  int newton_iterations = 1;
  /// Implicit only: Bullet's backtracking line search on the incremental potential. More robust
  /// under large steps, costlier (energy evaluations per trial).
  bool line_search = false;
};

/// The registry entries, with their parameter tables.
ModelInfo bullet_softbody_info();
ModelInfo bullet_deformable_info();

/// Direct construction, for tests. Throw InputError on invalid parameters or material.
std::unique_ptr<SoftBody> make_bullet_softbody(const TetMesh& mesh,
                                               const Material& material,
                                               const BulletSoftBodyParams& params);
std::unique_ptr<SoftBody> make_bullet_deformable(const TetMesh& mesh,
                                                 const Material& material,
                                                 const BulletDeformableParams& params);

}  // namespace softbench
