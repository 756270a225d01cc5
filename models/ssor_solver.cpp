// SPDX-License-Identifier: MIT
#include "models/ssor_solver.h"

#include "models/eisenstat_cg.h"
#include "models/team_loop.h"

#include <Eigen/LU>

#include <atomic>
#include <cmath>
#include <limits>
#include <span>

namespace softbench {
namespace {

/// out = B in for a row-major 3x3 block B.
[[gnu::always_inline]] inline void block_multiply(const double* block,
                                                  const double* in,
                                                  double* out) {
  out[0] = block[0] * in[0] + block[1] * in[1] + block[2] * in[2];
  out[1] = block[3] * in[0] + block[4] * in[1] + block[5] * in[2];
  out[2] = block[6] * in[0] + block[7] * in[1] + block[8] * in[2];
}

[[gnu::always_inline]] inline double dot3(const double* a, const double* b) {
  return a[0] * b[0] + a[1] * b[1] + a[2] * b[2];
}

/// Below this relative residual the iterate is at round-off: nothing is left to gain (an exact
/// preconditioner gets there before the error estimate has its window).
constexpr double kRoundoff = 1e-14;

}  // namespace

SsorConjugateGradientSolver::SsorConjugateGradientSolver(const LinearSolverOptions& options,
                                                         const BlockPattern& pattern)
    : options_(options),
      single_sweeps_(options.single_precision_sweeps
                     && options.tolerance >= kSingleSweepsTolerance),
      num_vertices_(pattern.num_vertices()),
      diagonal_(9 * static_cast<std::size_t>(pattern.num_vertices())),
      inverse_(9 * static_cast<std::size_t>(pattern.num_vertices())),
      coarse_(pattern, grow_aggregates(pattern, options.coarse_vertices)),
      residual_(pattern.size()),
      preconditioned_(pattern.size()),
      sweep_(pattern.size()),
      sweep_upper_(pattern.size()),
      direction_(pattern.size()),
      direction_upper_(pattern.size()),
      forward_(pattern.size()),
      chunk_sums_(static_cast<std::size_t>(pattern.num_chunks())) {
}

bool SsorConjugateGradientSolver::load(const BlockPattern& a) {
  coarse_.load_blocks(a);
  const bool single = single_sweeps_;
  if (single) {
    single_values_.resize(static_cast<std::size_t>(a.matrix().nonZeros()));
  }
  const double* values = a.matrix().valuePtr();
  float* copy = single_values_.data();
  const bool threaded = side_by_side(a.part_offsets());  // where over_ranges() uses threads
  bool factorised = false;
  std::atomic<bool> singular{false};
  maybe_parallel(threaded, [&] {
  // One thread factorises E (CHOLMOD on one thread: 1.3 ms on liver_x16) while the others
  // start on the vertices, and joins them when it is done.
#pragma omp single nowait
    factorised = coarse_.finish_load();
    team_blocks(threaded, num_vertices_, kVerticesPerBlock, [&](int first, int last) {
      for (int c = first; c < last; ++c) {
        const Eigen::Matrix3d block = a.get(a.vertex_block(c));
        Eigen::Matrix3d inverse;
        bool invertible = false;
        block.computeInverseWithCheck(inverse, invertible);
        if (!invertible || !inverse.allFinite()) {
          singular.store(true, std::memory_order_relaxed);
          return;
        }
        using RowMajor = Eigen::Matrix<double, 3, 3, Eigen::RowMajor>;
        Eigen::Map<RowMajor>(diagonal_.data() + 9 * c) = block;
        Eigen::Map<RowMajor>(inverse_.data() + 9 * c) = inverse;
      }
      if (single) {
        // Vertex c's columns end where c + 1's begin (the nonzero count after the last vertex).
        for (int i = a.column_values_begin(first); i < a.column_values_begin(last); ++i) {
          copy[i] = static_cast<float>(values[i]);
        }
      }
    });
  });
  return factorised && !singular.load(std::memory_order_relaxed);
}

SolveReport SsorConjugateGradientSolver::solve(const BlockPattern& a,
                                               const Eigen::VectorXd& b,
                                               Eigen::VectorXd& x,
                                               const double* offset) {
  const Eigen::VectorXd* known_product = take_start_product();
  SolveReport report;
  const double rhs_norm = b.norm();
  if (rhs_norm == 0.0) {
    x.setZero();
    return report;
  }
  if (!load(a)) {
    x.setConstant(std::numeric_limits<double>::quiet_NaN());
    report.succeeded = false;
    report.residual = std::numeric_limits<double>::quiet_NaN();
    return report;
  }
  const float* single = single_sweeps_ ? single_values_.data() : nullptr;
  const auto gather = [&a, single](int c, bool lower, const double* y, double* out) {
    if (single != nullptr) {
      a.neighbour_sum(c, lower, single, y, out);
    } else {
      a.neighbour_sum(c, lower, y, out);
    }
  };
  EnergyErrorEstimate estimate(
      reference_energy(a, x, offset, energy_floor(), direction_, chunk_sums_));
  const double* ax = start_product(a, x, known_product, forward_).data();

  const double* d = diagonal_.data();
  const double* inverse = inverse_.data();
  const double* bs = b.data();
  double* xs = x.data();
  double* r = residual_.data();
  double* z = preconditioned_.data();
  double* s = sweep_.data();
  double* us = sweep_upper_.data();
  double* t = direction_.data();
  double* ut = direction_upper_.data();
  double* y = forward_.data();

  // The sweeps run over the pattern's parts side by side (no block joins two of them) and over
  // the separator alone: after the parts forward, before them backward, as a vertex's
  // predecessors in its sweep are then done. One part: the sweeps in vertex order. The other
  // loops run over the parts and the separator side by side.
  const std::span<const int> ranges = a.part_offsets();
  const std::span<const int> parts = ranges.first(ranges.size() - 1);
  const int separator = ranges[ranges.size() - 2];
  const int n = num_vertices_;
  const auto forward = [&](const auto& rows) {
    RangeSums sums = over_ranges(parts, rows);
    sums += rows(separator, n);
    return sums;
  };
  const auto backward = [&](const auto& rows) {
    rows(separator, n);
    over_ranges(parts, rows);
  };

  // Row c of a forward sweep: out_c = D_c^-1 (in_c - sum over n < c of A_cn out_n) (`in` may be
  // `out`: each row reads its own entry before writing it).
  const auto forward_row = [&gather, inverse](int c, const double* in, double* out) {
    double lower[3];
    gather(c, /*lower=*/true, out, lower);
    const double rest[3] = {in[3 * c] - lower[0], in[3 * c + 1] - lower[1],
                            in[3 * c + 2] - lower[2]};
    block_multiply(inverse + 9 * c, rest, out + 3 * c);
  };

  // The start: r0 = b - A x0, then x0 += W mu and r0 -= A W mu with E mu = W^T r0, so that
  // W^T r0 = 0 (the coarse level solved exactly).
  over_ranges(ranges, [&](int first, int last) {
    for (int i = 3 * first; i < 3 * last; ++i) {
      r[i] = bs[i] - ax[i];
    }
    return RangeSums{};
  });
  coarse_.restrict_to_coarse(ranges, r);
  coarse_.solve();
  over_ranges(ranges, [&](int first, int last) {
    for (int c = first; c < last; ++c) {
      double moved[3];
      coarse_.product_at(c, /*upper=*/false, moved);
      const double* shift = coarse_.translation(c);
      for (int k = 0; k < 3; ++k) {
        xs[3 * c + k] += shift[k];
        r[3 * c + k] -= moved[k];
      }
    }
    return RangeSums{};
  });
  // r^ = (D + L)^-1 r0 in place (CG runs on the correction from x0, so x^ starts at 0), z =
  // D r^, r^ . z; and the scale of round-off for the transformed residual: |D^-1 b|, the
  // transformed right-hand side's size up to the coupling of the sweep (a floor at 1e-14 of it
  // needs no more).
  const RangeSums start = forward([&](int first, int last) {
    RangeSums part;
    for (int c = first; c < last; ++c) {
      forward_row(c, r, r);
      block_multiply(d + 9 * c, r + 3 * c, z + 3 * c);
      part.first += dot3(r + 3 * c, z + 3 * c);
      double scaled[3];
      block_multiply(inverse + 9 * c, bs + 3 * c, scaled);
      part.second += dot3(scaled, scaled);
    }
    return part;
  });
  double rz = start.first;
  const double roundoff = kRoundoff * std::sqrt(start.second);
  direction_.setZero();
  direction_upper_.setZero();

  report.converged = rz == 0.0;
  double beta = 0.0;
  while (!report.converged && report.iterations < options_.max_iterations) {
    ++report.iterations;
    // Backward: s = (D + U)^-1 z, U s, and (A W)^T s range by range.
    coarse_.clear_restriction(ranges);
    backward([&](int first, int last) {
      double* slice = coarse_.restriction_slice(ranges, first, last);
      for (int c = last - 1; c >= first; --c) {
        double upper[3];
        gather(c, /*lower=*/false, s, upper);
        const double rest[3] = {z[3 * c] - upper[0], z[3 * c + 1] - upper[1],
                                z[3 * c + 2] - upper[2]};
        block_multiply(inverse + 9 * c, rest, s + 3 * c);
        us[3 * c] = upper[0];
        us[3 * c + 1] = upper[1];
        us[3 * c + 2] = upper[2];
        coarse_.add_product(c, s + 3 * c, slice);
      }
      return RangeSums{};
    });
    // mu = E^-1 (A W)^T s; t = beta t + s - W mu, U t likewise, and p . A^ p = t^T A t.
    coarse_.finish_restriction(ranges);
    coarse_.solve();
    const double curvature = over_ranges(ranges, [&](int first, int last) {
                               RangeSums part;
                               for (int c = first; c < last; ++c) {
                                 double moved[3];
                                 coarse_.product_at(c, /*upper=*/true, moved);
                                 const double* shift = coarse_.translation(c);
                                 for (int k = 0; k < 3; ++k) {
                                   t[3 * c + k] = beta * t[3 * c + k] + s[3 * c + k] - shift[k];
                                   ut[3 * c + k] = beta * ut[3 * c + k] + us[3 * c + k] - moved[k];
                                 }
                                 double dt[3];
                                 block_multiply(d + 9 * c, t + 3 * c, dt);
                                 part.first +=
                                     dot3(t + 3 * c, dt) + 2.0 * dot3(t + 3 * c, ut + 3 * c);
                               }
                               return part;
                             }).first;
    if (!(curvature > 0.0) || !std::isfinite(rz)) {
      break;  // not positive definite, or NaN: stop with what we have
    }
    const double alpha = rz / curvature;
    report.error = estimate.add(report.iterations, alpha * rz);
    // Forward: y = (D + L)^-1 U t, A^ p = t + y; x += alpha t, r^ -= alpha A^ p, z = D r^.
    const RangeSums sums = forward([&](int first, int last) {
      RangeSums part;
      for (int c = first; c < last; ++c) {
        forward_row(c, ut, y);
        double rv[3];
        for (int k = 0; k < 3; ++k) {
          rv[k] = r[3 * c + k] - alpha * (t[3 * c + k] + y[3 * c + k]);
          r[3 * c + k] = rv[k];
          xs[3 * c + k] += alpha * t[3 * c + k];
        }
        block_multiply(d + 9 * c, rv, z + 3 * c);
        part.first += dot3(rv, z + 3 * c);
        part.second += dot3(rv, rv);
      }
      return part;
    });
    if (std::sqrt(sums.second) <= roundoff || sums.first == 0.0
        || estimate.met(report.iterations, options_.tolerance)) {
      report.converged = true;
      break;
    }
    beta = sums.first / rz;
    rz = sums.first;
  }

  // The system's residual b - A x = (D + L) r^ (r^ is only read: every range at once).
  const double true_squared = over_ranges(ranges, [&](int first, int last) {
                                RangeSums part;
                                for (int c = first; c < last; ++c) {
                                  double lower[3];
                                  gather(c, /*lower=*/true, r, lower);
                                  double own[3];
                                  block_multiply(d + 9 * c, r + 3 * c, own);
                                  for (int k = 0; k < 3; ++k) {
                                    part.first += (own[k] + lower[k]) * (own[k] + lower[k]);
                                  }
                                }
                                return part;
                              }).first;
  report.residual = std::sqrt(true_squared) / rhs_norm;
  report.succeeded = std::isfinite(report.residual) && x.allFinite();
  return report;
}

std::size_t SsorConjugateGradientSolver::memory_bytes() const {
  return (diagonal_.capacity() + inverse_.capacity() + chunk_sums_.capacity()) * sizeof(double)
         + single_values_.capacity() * sizeof(float) + coarse_.memory_bytes()
         + 7 * static_cast<std::size_t>(residual_.size()) * sizeof(double);
}

}  // namespace softbench
