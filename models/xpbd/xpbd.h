// SPDX-License-Identifier: MIT
#pragma once

#include "geometry/tet_mesh.h"
#include "models/material.h"
#include "models/model_registry.h"
#include "models/soft_body.h"

#include <memory>

namespace softbench {

// Extended position-based dynamics (Macklin, Mueller & Chentanez 2016, "XPBD: position-based
// simulation of compliant constrained dynamics") with small steps (Macklin, Storey, Lu,
// Terdiman, Chentanez, Jeschke & Mueller 2019, "Small steps in physics simulation") on the
// stable neo-Hookean constraints of Macklin & Mueller 2021 ("A constraint-based formulation of
// stable neo-Hookean materials"). Lumped masses (density * volume / 4 per tet corner).
//
// Constraints, two per tet of rest volume V with deformation gradient F (I_C = tr(F^T F),
// J = det F), on the reference's own energy (neo_hookean, stable_neo_hookean.h: Smith, de Goes
// & Kim 2018, with its parameters mu, lambda, alpha from the material's E and nu):
//   deviatoric   C_D = sqrt(I_C - log(I_C + 1)),   compliance 1 / (mu V),
//   hydrostatic  C_H = J - alpha,                  compliance 1 / (lambda V),
// i.e. the energy V (mu/2 (I_C - log(I_C + 1)) + lambda/2 (J - alpha)^2), Smith et al.'s up to a
// constant. Macklin & Mueller's constraints are C_D = sqrt(I_C) and C_H = J - (1 + mu/lambda):
// the same energy without the log term, whose shear stiffness stays mu at large strain where
// Smith et al.'s grows from 3/4 mu toward mu. With them the liver hanging from its lowest tenth
// in x settled 12% lower than the reference's, converged in substeps (a different material at
// the scenes' strains, not a different solution), and liver_press's probe met 0.13 N where the
// reference meets 0.40 N; the log term costs one log1p per tet per sweep and makes xpbd converge
// to the reference's material at any strain. At small strain both are linear elasticity with
// the material's E and nu. Everything comes from the material: there is no stiffness knob, and
// since XPBD's compliance is a material constant (unlike PBD's stiffness per iteration) the
// material does not change with `substeps` or `iterations`; they only set how closely the
// implicit step is solved.
//
// Step (dt, split into n substeps of h = dt / n; Macklin 2019; n = `substeps`, or more where
// the stiffest tet needs a shorter h to stay stable: XpbdParams::stability_ratio): per substep
//   v <- v / (1 + h mass_damping)                       (an implicit drag)
//   x~ = x + h v + h^2 (g + f_ext / m),  x <- x~, exact holds placed (below)
//   `iterations` Gauss-Seidel sweeps over the tets (in a fixed order, below), lambda reset to
//   0 per substep; each tet solves its two constraints together, linearised (a 2x2 system):
//     [g_i . W g_j + alpha~_i delta_ij] dlambda_j = -C_i - alpha~_i lambda_i,
//     alpha~ = compliance / h^2,  x_a += W_a (g_D,a dlambda_D + g_H,a dlambda_H),
//   then the penalty attachments, then the exact holds placed again;
//   v = (x - x_old) / h.
// Why the two constraints are solved together rather than one after the other: at rest neither
// is zero (C_D = sqrt(3 - log 4), C_H = 1 - alpha) and only their forces cancel. Projected one after the
// other from lambda = 0, the first moves the tet before the second answers and the two moves
// do not cancel, so a body at rest would not stay there; solved together, the two corrections cancel exactly
// wherever F is a rotation (their gradients are then parallel), so rest is a fixed point of
// every sweep. The 2x2 system's determinant is at least alpha~_D alpha~_H > 0, so a tet whose
// gradients vanish (collapsed to a point: C_D's gradient F / |F| is undefined, and is taken as
// zero below 1e-150) only stops moving; an inverted tet has J < 0 and C_H's gradient cof F
// pushes det F back up.
//
// Holds (StepInput::constraints): an exact hold gives its vertex the inverse-mass matrix
// (I - held) / m in the projections (no move along the held directions) and places it with
// PositionConstraint::place after the prediction and after each sweep, its target moving in a
// straight line from where the vertex started the step to the step's target, reached at the
// last substep, so the step ends on the target (the full hold: exactly) and the held vertex's
// velocity is (target - x) / dt. A finite stiffness k is a compliant attachment
// C = held (x - target), compliance 1 / k. constraint_forces(): per held vertex, by momentum
// balance over each substep, held (m (x - x~) - sum_k g_k dlambda_k) / h^2 (the impulses of
// the tets' constraints removed), averaged over the substeps: at rest they balance the weight.
//
// elastic_energy(): the reference's, sum V Psi(F) (neo_hookean::energy_density: 0 at rest,
// ~round-off^2 after a rigid motion); its negative gradient is the force the constraints apply
// once converged.
//
// StepStats: iterations = substeps * iterations (sweeps); residual = the largest
// |C + alpha~ lambda| over the tets' constraints at the end of the step (dimensionless: a
// strain for C_D, a volume ratio for C_H), what the last substep left of its implicit
// equations (0 if solved); max_constraint_error = the largest |held (target - x)| over exact
// holds (round-off); finite = false once a NaN or Inf appears (the step stops there).
//
// The sweep (xpbd_step.cpp): per tet 80 bytes (S = Dm^-1 Dm^-T, det Dm^-1, 1 / V, the
// vertices), F never formed (the gradients come from the edges and S, cof of the edges), two
// tets that share no vertex projected together in SSE2 pairs with the same operations as
// one alone. The order is mesh order, except that each tet is the first of the next 64 that
// shares no vertex with the two before it (xpbd.cpp), so most consecutive tets can be paired;
// Gauss-Seidel in that fixed order is still Gauss-Seidel.
//
// Threads: none. The sweep runs on one thread, so every run has the same bits at any thread
// count. A graph-coloured parallel sweep was not tried: the liver's whole sweep takes ~0.25 ms
// (models/README.md), so each colour's share would be a few microseconds, the order of a
// barrier between threads on the shared 2-core machine, and colouring changes the order.
//
// Against the neo_hookean reference: the same energy, so the static sag of a cantilever under
// low gravity agrees within 0.04% at 32 substeps (0.6% at 8), and on liver_press the peak tool
// force is 0.387 N against the reference's 0.398 N at the default 10 substeps.

struct XpbdParams {
  /// Substeps per step (Macklin 2019: many substeps of one sweep beat few of many). More:
  /// closer to the implicit solution (the sweep's fixed point is the energy's equilibrium only
  /// as h -> 0: its force imbalance falls as 1 / substeps^2), stiffer materials stay stable;
  /// cost proportional. Default 10 (measured on the liver hanging from its lowest tenth in x,
  /// the mean sag relative to its 40-substep value: 3 substeps +7.3%, 5 +2.1%, 10 +0.4%,
  /// 20 +0.1%; volume gained 17%, 12%, 10.1%, 9.6%, against 9.5%): the cheapest count within
  /// 1% of converged, about 2.5 ms a step on one core.
  int substeps = 10;
  /// Gauss-Seidel sweeps per substep (lambda accumulated over them). More: closer to the
  /// substep's implicit solution; Macklin 2019 found substeps the better use of the same work.
  int iterations = 1;
  /// 1/s, a drag on every vertex's velocity (Rayleigh mass damping alpha: force -alpha m v,
  /// applied implicitly per substep). 0: only the step's own (small) numerical damping.
  double mass_damping = 0.0;
  /// The largest (h omega)^2 a substep may have, omega = XpbdModel::stability_rate() (the
  /// stiffest tet's shear rate, sqrt(mu V sum_a |grad N_a|^2 / m_a)): a step takes more than
  /// `substeps` when dt / substeps is longer. Why a bound: at rest C_D and C_H are not zero and
  /// their gradients are parallel (both along F), so a body's shear stiffness lives wholly in
  /// the curvature of the two constraints under their large multipliers, which the linearised
  /// projection leaves out: the sweep integrates shear explicitly, and like an explicit method
  /// diverges above a substep bound. Measured on a beam of 1 cm cubes perturbed by 1e-9 m, E from
  /// 3 kPa to 100 MPa, dt 1/60 s: at rest for 20 steps up to a ratio of 1.6, thrown off from 3.3
  /// at every E (without the bound, 10 substeps of a 10 MPa beam threw a vertex 7 cm in the
  /// first step). Default 0.5, a margin for compressed tets; the liver at 1/60 s needs 10
  /// (its stiffest tet: omega 403 /s, the median tet 154 /s). 0: no bound.
  double stability_ratio = 0.5;
};

/// The registry entry ("xpbd") with the parameter table.
ModelInfo xpbd_info();

/// Direct construction, for tests and benchmarks. Throws InputError on invalid parameters or
/// material.
std::unique_ptr<SoftBody> make_xpbd(const TetMesh& mesh,
                                    const Material& material,
                                    const XpbdParams& params);

}  // namespace softbench
