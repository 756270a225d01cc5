// SPDX-License-Identifier: MIT
#pragma once

#include "geometry/tet_mesh.h"
#include "models/calibration_record.h"
#include "models/material.h"
#include "models/model_registry.h"
#include "models/soft_body.h"

#include <memory>
#include <optional>

namespace softbench {

// Mass-spring model on the edges of the tet mesh (the thesis's "tetrahedral connectivity",
// section 3.2), with lumped masses from the material density.
//
// Forces on vertex i from spring (i, j) with rest length L, current length l, direction
// d = (x_j - x_i) / l: elastic k (l - L) d, dashpot c ((v_j - v_i) . d) d with
// c = damping + rayleigh_stiffness * k; mass damping -c_m m_i v_i. Integrators: symplectic
// (semi-implicit) Euler, v += dt f / m then x += dt v; and backward Euler linearised once (Baraff
// & Witkin 1998): (M - dt D - dt^2 K) dv = dt (f + dt K v), with the spring Jacobian
// K_e = -k [d d^T + max(0, 1 - L/l) (I - d d^T)] (the compressive geometric term clamped so K
// stays negative semi-definite and the system SPD).
// Exact constraints are eliminated: the constrained vertex ends the step on its target with
// v = (target - x) / dt, and the reaction is the force its row of the system needed.
// StepStats.residual: the constrained system's relative residual |A dv - b| / |b| (CG: from its
// recursively updated residual; CHOLMOD: computed); 0 for symplectic Euler.
//
// Defaults follow the material: springs from Young's modulus (Van Gelder 1998) and no damping
// beyond what backward Euler's numerical damping does; the thesis's k = 180 N/m and c = 5 N s/m
// are `"stiffness_from": "given", "stiffness": 180, "damping": 5`.
//
// The implicit step's "cg" solve is matrix-free (spring_system.h): CG on four coefficients per
// spring, preconditioned by symmetric Gauss-Seidel in Eisenstat's form, warm-started from the
// best combination of the last four solutions. Cost on the liver (1215 vertices, 6802 springs,
// E 3000 Pa, dt 1/60 s, one core; bench/mass_spring_bench.cpp): 0.6-0.9 ms a step as the
// machine's speed varies, 4.3 iterations, about 0.3x corotational_fem's step in the same run;
// models/README.md has the breakdown.

struct MassSpringParams {
  enum class StiffnessFrom { kGiven, kYoungModulus };
  enum class Integrator { kSymplecticEuler, kImplicitEuler };
  enum class LinearSolver { kCholmod, kConjugateGradient };
  enum class Preconditioner { kSsor, kBlockJacobi };

  /// N/m per spring, used when stiffness_from is "given" (the thesis: 180). Stiffer: smaller
  /// deformation, and a smaller stable dt for the symplectic integrator.
  double stiffness = 180.0;
  /// "young_modulus" (default): k_e = E * sum of the volumes of the tets sharing edge e / L_e^2
  /// (Van Gelder 1998's volume weighting), so the springs follow the material and the mesh
  /// resolution; "given": every spring has `stiffness`.
  StiffnessFrom stiffness_from = StiffnessFrom::kYoungModulus;
  /// Multiplies every spring's stiffness (either source). Van Gelder's springs are not exact
  /// for a tet mesh (a spring network cannot represent Poisson's ratio): `softbench calibrate`
  /// fits this scale so the springs sag and press as the material does.
  double stiffness_scale = 1.0;
  /// N s/m per spring, a dashpot along the spring, the same for every spring (the thesis: 5).
  double damping = 0.0;
  /// s, Rayleigh stiffness damping: each spring also gets a dashpot rayleigh_stiffness * k_e
  /// along it, so the damping follows the springs' stiffness (and so the material and the mesh)
  /// and damps a mode of frequency omega at a ratio of about rayleigh_stiffness * omega / 2.
  double rayleigh_stiffness = 0.0;
  /// 1/s, Rayleigh mass damping: force -mass_damping * m * v on every vertex (air-like drag).
  double mass_damping = 0.0;
  /// Symplectic Euler is cheap per step but stable only for dt below ~2/omega_max; implicit
  /// Euler is stable at any dt but damps high frequencies numerically.
  Integrator integrator = Integrator::kImplicitEuler;
  /// Implicit Euler only: CHOLMOD refactorises every step (exact; ~20 ms on the liver);
  /// "cg": matrix-free preconditioned CG, warm-started, stopping at cg_tolerance.
  LinearSolver solver = LinearSolver::kConjugateGradient;
  /// "cg" only: "ssor" (symmetric Gauss-Seidel sweeps in Eisenstat's form; about half the
  /// iterations of block Jacobi at about the same cost per iteration) or "block_jacobi" (the
  /// inverse 3x3 vertex blocks).
  Preconditioner preconditioner = Preconditioner::kSsor;
  /// Relative energy-norm error (LinearSolverOptions::tolerance), corotational_fem's default:
  /// one accuracy rule for the implicit models, so their speeds compare at the same accuracy.
  double cg_tolerance = 1e-3;
  int cg_max_iterations = 200;  ///< cap per step; hitting it is reported in StepStats
  /// Set by `softbench calibrate` (stiffness_scale fitted to a reference); null otherwise.
  std::optional<CalibrationRecord> calibrated;
};

/// The registry entry ("mass_spring") with the parameter table.
ModelInfo mass_spring_info();

/// Direct construction, for tests. Throws InputError on invalid parameters or material.
std::unique_ptr<SoftBody> make_mass_spring(const TetMesh& mesh,
                                           const Material& material,
                                           const MassSpringParams& params);

}  // namespace softbench
