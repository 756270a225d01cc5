// SPDX-License-Identifier: MIT
#pragma once

#include "models/system_solver.h"

#include <cmath>

namespace softbench {

/// r . z and |r|^2 of the start.
struct EisenstatStart {
  double rz = 0.0;
  double residual_squared = 0.0;
};

/// The start of eisenstat_iterations from y = (D + L)^-1 (b - U x0): r^ = y - x0 (which by
/// A = (D + L) + U is (D + L)^-1 (b - A x0)), z = D r^ and p = z. `y` may be `r` itself.
template <class ApplyD>
EisenstatStart eisenstat_start(int num_vertices,
                               const double* y,
                               const double* x0,
                               double* r,
                               double* z,
                               double* p,
                               const ApplyD& apply_d) {
  EisenstatStart start;
  for (int v = 0; v < num_vertices; ++v) {
    const double rv[3] = {y[3 * v] - x0[3 * v], y[3 * v + 1] - x0[3 * v + 1],
                          y[3 * v + 2] - x0[3 * v + 2]};
    double zv[3];
    apply_d(v, rv, zv);
    for (int a = 0; a < 3; ++a) {
      r[3 * v + a] = rv[a];
      z[3 * v + a] = zv[a];
      p[3 * v + a] = zv[a];
    }
    start.rz += rv[0] * zv[0] + rv[1] * zv[1] + rv[2] * zv[2];
    start.residual_squared += rv[0] * rv[0] + rv[1] * rv[1] + rv[2] * rv[2];
  }
  return start;
}

/// The iterations of conjugate gradients preconditioned by symmetric Gauss-Seidel (SSOR with
/// omega = 1) in Eisenstat's form (1981), shared by the block-matrix solver (ssor_solver.h) and
/// the mass-spring model's spring system: CG on A^ = (D + L)^-1 A (D + U)^-1 with the
/// preconditioner z = D r^, so an iteration costs one backward and one forward sweep. The
/// caller sets up x^ = (D + U) x0, r^, z = D r^, p = z and rz = r^ . z, and afterwards turns
/// x^ back into x = (D + U)^-1 x^.
///
/// `sweeps(beta)` sets p = z + beta p and q = A^ p (the two sweeps) and returns p . q.
/// `apply_d(v, in, out)` sets out = D_v in for vertex v's 3x3 block. Vectors are 3 per vertex.
/// The loop stops once the energy-norm estimate meets `tolerance` (EnergyErrorEstimate), the
/// residual |r^| is at most `roundoff`, r^ . z is zero, or at `max_iterations`; `report` gets
/// the iterations, the estimate and whether it converged.
template <class Sweeps, class ApplyD>
void eisenstat_iterations(int num_vertices,
                          double* x_hat,
                          double* r,
                          double* z,
                          const double* p,
                          const double* q,
                          double rz,
                          double roundoff,
                          double tolerance,
                          int max_iterations,
                          EnergyErrorEstimate& estimate,
                          SolveReport& report,
                          const Sweeps& sweeps,
                          const ApplyD& apply_d) {
  double beta = 0.0;
  while (!report.converged && report.iterations < max_iterations) {
    ++report.iterations;
    const double curvature = sweeps(beta);
    if (!(curvature > 0.0) || !std::isfinite(rz)) {
      break;  // not positive definite, or NaN: stop with what we have
    }
    const double alpha = rz / curvature;
    report.error = estimate.add(report.iterations, alpha * rz);
    double rz_next = 0.0;
    double residual_squared = 0.0;
    for (int v = 0; v < num_vertices; ++v) {
      // Kept in locals: a vector load of values just stored one by one would stall.
      double rv[3];
      for (int a = 0; a < 3; ++a) {
        x_hat[3 * v + a] += alpha * p[3 * v + a];
        rv[a] = r[3 * v + a] - alpha * q[3 * v + a];
        r[3 * v + a] = rv[a];
      }
      double zv[3];
      apply_d(v, rv, zv);
      z[3 * v] = zv[0];
      z[3 * v + 1] = zv[1];
      z[3 * v + 2] = zv[2];
      rz_next += rv[0] * zv[0] + rv[1] * zv[1] + rv[2] * zv[2];
      residual_squared += rv[0] * rv[0] + rv[1] * rv[1] + rv[2] * rv[2];
    }
    if (std::sqrt(residual_squared) <= roundoff || rz_next == 0.0
        || estimate.met(report.iterations, tolerance)) {
      report.converged = true;
      break;
    }
    beta = rz_next / rz;
    rz = rz_next;
  }
}

}  // namespace softbench
