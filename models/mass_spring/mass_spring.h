// SPDX-License-Identifier: MIT
#pragma once

#include "geometry/tet_mesh.h"
#include "models/material.h"
#include "models/model_registry.h"
#include "models/soft_body.h"

#include <memory>

namespace softbench {

// Mass-spring model on the edges of the tet mesh (the thesis's "tetrahedral connectivity",
// section 3.2), with lumped masses from the material density.
//
// Forces on vertex i from spring (i, j) with rest length L, current length l, direction
// d = (x_j - x_i) / l: elastic k (l - L) d, dashpot c ((v_j - v_i) . d) d; mass damping
// -c_m m_i v_i. Integrators: symplectic (semi-implicit) Euler, v += dt f / m then x += dt v; and
// backward Euler linearised once (Baraff & Witkin 1998): (M - dt D - dt^2 K) dv = dt (f + dt K v),
// with the spring Jacobian K_e = -k [d d^T + max(0, 1 - L/l) (I - d d^T)] (the compressive
// geometric term clamped so K stays negative semi-definite and the system SPD).
// Exact constraints are eliminated: the constrained vertex ends the step on its target with
// v = (target - x) / dt, and the reaction is the force its row of the system needed.
// StepStats.residual: the CG relative residual, or for CHOLMOD |A dv - b| / |b| of the
// constraint-eliminated system; 0 for symplectic Euler.

struct MassSpringParams {
  enum class StiffnessFrom { kGiven, kYoungModulus };
  enum class Integrator { kSymplecticEuler, kImplicitEuler };
  enum class LinearSolver { kCholmod, kConjugateGradient };

  /// N/m per spring, used when stiffness_from is "given" (the thesis: 180). Stiffer: smaller
  /// deformation, and a smaller stable dt for the symplectic integrator.
  double stiffness = 180.0;
  /// "given": every spring has `stiffness`; "young_modulus": k_e = E * sum of the volumes of
  /// the tets sharing edge e / L_e^2 (Van Gelder 1998's volume weighting), so the springs follow
  /// the material and the mesh resolution.
  StiffnessFrom stiffness_from = StiffnessFrom::kGiven;
  /// N s/m per spring, along the spring (the thesis: 5). More: faster settling, less rebound.
  double damping = 5.0;
  /// 1/s, force -mass_damping * m * v on every vertex (air-like drag).
  double mass_damping = 0.0;
  /// Symplectic Euler is cheap per step but stable only for dt below ~2/omega_max; implicit
  /// Euler is stable at any dt but damps high frequencies numerically.
  Integrator integrator = Integrator::kImplicitEuler;
  /// Implicit Euler only: CHOLMOD refactorises every step (exact); warm-started Jacobi-PCG
  /// stops at cg_tolerance (fast, approximate).
  LinearSolver solver = LinearSolver::kConjugateGradient;
  double cg_tolerance = 1e-6;   ///< relative energy-norm error (LinearSolverOptions::tolerance)
  int cg_max_iterations = 200;  ///< cap per step; hitting it is reported in StepStats
};

/// The registry entry ("mass_spring") with the parameter table.
ModelInfo mass_spring_info();

/// Direct construction, for tests. Throws InputError on invalid parameters or material.
std::unique_ptr<SoftBody> make_mass_spring(const TetMesh& mesh,
                                           const Material& material,
                                           const MassSpringParams& params);

}  // namespace softbench
