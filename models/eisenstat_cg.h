// SPDX-License-Identifier: MIT
#pragma once

#include "models/system_solver.h"

#include <array>
#include <cmath>
#include <cstddef>
#include <span>
#include <stdexcept>
#include <type_traits>

namespace softbench {

/// At most this many vertex ranges in a loop over_ranges() runs side by side.
inline constexpr int kMaxRanges = 17;

/// Two sums of a loop over vertices.
struct RangeSums {
  double first = 0.0;
  double second = 0.0;
  RangeSums& operator+=(const RangeSums& other) {
    first += other.first;
    second += other.second;
    return *this;
  }
};

/// Whether over_ranges() runs these ranges side by side: two or more of them have vertices.
inline bool side_by_side(std::span<const int> offsets) {
  int filled = 0;
  for (std::size_t k = 0; k + 1 < offsets.size(); ++k) {
    filled += offsets[k + 1] > offsets[k] ? 1 : 0;
  }
  return filled > 1;
}

/// body(first, last) over the vertex ranges [offsets[k], offsets[k + 1]), side by side (an
/// OpenMP thread each) when two or more have vertices, what each returns (a value-initialised
/// type with +=, RangeSums for most loops) added in the ranges' order: the same whatever the
/// thread count. The ranges must not share the values a body writes (a vector loop over
/// vertices; BlockPattern::part_offsets() for a sweep's parts).
template <class Body>
auto over_ranges(std::span<const int> offsets, const Body& body) {
  using Sums = std::invoke_result_t<const Body&, int, int>;
  const auto ranges = static_cast<int>(offsets.size()) - 1;
  if (ranges > kMaxRanges) {
    throw std::invalid_argument("over_ranges: more than kMaxRanges ranges");
  }
  std::array<Sums, kMaxRanges> sums{};
  const auto run = [&](int k) {
    sums[static_cast<std::size_t>(k)] =
        body(offsets[static_cast<std::size_t>(k)], offsets[static_cast<std::size_t>(k) + 1]);
  };
  if (side_by_side(offsets)) {
    // Dynamic: the ranges differ in size (a sweep's separator is small), and whichever thread
    // is free takes the next.
#pragma omp parallel for schedule(dynamic, 1)
    for (int k = 0; k < ranges; ++k) {
      run(k);
    }
  } else {
    // One range with vertices (a small mesh's whole body and its empty separator): a plain
    // loop. A region would only wait (under a busy second core, for a descheduled thread), and
    // even one made serial by an if clause pays libgomp's team and schedule bookkeeping: the
    // corotational FEM's step on the liver, which loops over ranges about fifty times, took
    // 1.05 ms with the if clause and 0.92 ms without a region.
    for (int k = 0; k < ranges; ++k) {
      run(k);
    }
  }
  Sums total{};
  for (int k = 0; k < ranges; ++k) {
    total += sums[static_cast<std::size_t>(k)];
  }
  return total;
}

/// r . z and |r|^2 of the start.
struct EisenstatStart {
  double rz = 0.0;
  double residual_squared = 0.0;
};

/// The start of eisenstat_iterations from y = (D + L)^-1 (b - U x0): r^ = y - x0 (which by
/// A = (D + L) + U is (D + L)^-1 (b - A x0)), z = D r^ and p = z. `y` may be `r` itself.
/// `ranges`: vertex ranges the vector loops may run on side by side (over_ranges()).
template <class ApplyD>
EisenstatStart eisenstat_start(std::span<const int> ranges,
                               const double* y,
                               const double* x0,
                               double* r,
                               double* z,
                               double* p,
                               const ApplyD& apply_d) {
  const RangeSums sums = over_ranges(ranges, [&](int first, int last) {
    RangeSums part;
    for (int v = first; v < last; ++v) {
      const double rv[3] = {y[3 * v] - x0[3 * v], y[3 * v + 1] - x0[3 * v + 1],
                            y[3 * v + 2] - x0[3 * v + 2]};
      double zv[3];
      apply_d(v, rv, zv);
      for (int a = 0; a < 3; ++a) {
        r[3 * v + a] = rv[a];
        z[3 * v + a] = zv[a];
        p[3 * v + a] = zv[a];
      }
      part.first += rv[0] * zv[0] + rv[1] * zv[1] + rv[2] * zv[2];
      part.second += rv[0] * rv[0] + rv[1] * rv[1] + rv[2] * rv[2];
    }
    return part;
  });
  return {sums.first, sums.second};
}

/// The iterations of conjugate gradients preconditioned by symmetric Gauss-Seidel (SSOR with
/// omega = 1) in Eisenstat's form (1981), for the mass-spring model's spring system (the
/// block-matrix solver, ssor_solver.h, runs its own deflated form of them): CG on
/// A^ = (D + L)^-1 A (D + U)^-1 with the preconditioner z = D r^, so an iteration costs one
/// backward and one forward sweep. The caller sets up x^ = (D + U) x0, r^, z = D r^, p = z and
/// rz = r^ . z, and afterwards turns x^ back into x = (D + U)^-1 x^.
///
/// `sweeps(beta)` sets p = z + beta p and q = A^ p (the two sweeps) and returns p . q.
/// `apply_d(v, in, out)` sets out = D_v in for vertex v's 3x3 block. Vectors are 3 per vertex;
/// their loops run over `ranges` (over_ranges()).
/// The loop stops once the energy-norm estimate meets `tolerance` (EnergyErrorEstimate), the
/// residual |r^| is at most `roundoff`, r^ . z is zero, or at `max_iterations`; `report` gets
/// the iterations, the estimate and whether it converged.
template <class Sweeps, class ApplyD>
void eisenstat_iterations(std::span<const int> ranges,
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
    const RangeSums sums = over_ranges(ranges, [&](int first, int last) {
      RangeSums part;
      for (int v = first; v < last; ++v) {
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
        part.first += rv[0] * zv[0] + rv[1] * zv[1] + rv[2] * zv[2];
        part.second += rv[0] * rv[0] + rv[1] * rv[1] + rv[2] * rv[2];
      }
      return part;
    });
    const double rz_next = sums.first;
    const double residual_squared = sums.second;
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
