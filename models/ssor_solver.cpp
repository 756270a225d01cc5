// SPDX-License-Identifier: MIT
#include "models/ssor_solver.h"

#include "models/eisenstat_cg.h"

#include <Eigen/Cholesky>
#include <Eigen/LU>

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
      num_vertices_(pattern.num_vertices()),
      diagonal_(9 * static_cast<std::size_t>(pattern.num_vertices())),
      inverse_(9 * static_cast<std::size_t>(pattern.num_vertices())),
      row_sums_(9 * static_cast<std::size_t>(pattern.num_vertices())),
      residual_(pattern.size()),
      preconditioned_(pattern.size()),
      direction_(pattern.size()),
      product_(pattern.size()),
      sweep_(pattern.size()),
      carry_(pattern.size()),
      transformed_(pattern.size()),
      chunk_sums_(static_cast<std::size_t>(pattern.num_chunks())) {
}

bool SsorConjugateGradientSolver::load_columns(const BlockPattern& a) {
  // Column c's strips: sums(i, k) adds entry (n, i) of column (c, k) over the neighbours n, i.e.
  // (Z^T A)'s block at c, the transpose of (A Z)_c (A is symmetric); the strip of c itself is
  // D_c. One pass over the values for both, range by range (the pattern's parts and separator
  // side by side), Z^T A Z summed in the ranges' order.
  /// A range's part of Z^T A Z, and whether its diagonal blocks were all invertible.
  struct CoarseSums {
    Eigen::Matrix3d coarse = Eigen::Matrix3d::Zero();
    bool invertible = true;
    CoarseSums& operator+=(const CoarseSums& other) {
      coarse += other.coarse;
      invertible = invertible && other.invertible;
      return *this;
    }
  };
  const CoarseSums total = over_ranges(a.part_offsets(), [&](int first, int last) {
    CoarseSums part;
    for (int c = first; c < last; ++c) {
      const auto degree = static_cast<int>(a.neighbours(c).size());
      const int own = a.own_slot(c);
      const double* column = a.matrix().valuePtr() + a.column_values_begin(c);
      Eigen::Map<Eigen::Matrix3d> sums(row_sums_.data() + 9 * static_cast<std::size_t>(c));
      Eigen::Matrix3d block;
      for (int k = 0; k < 3; ++k) {
        double s0 = 0.0;
        double s1 = 0.0;
        double s2 = 0.0;
        const double* strip = column + 3 * degree * k;
        for (int slot = 0; slot < degree; ++slot) {
          s0 += strip[3 * slot];
          s1 += strip[3 * slot + 1];
          s2 += strip[3 * slot + 2];
        }
        sums(0, k) = s0;
        sums(1, k) = s1;
        sums(2, k) = s2;
        block.col(k) = Eigen::Map<const Eigen::Vector3d>(strip + 3 * own);
      }
      part.coarse += sums;
      Eigen::Matrix3d inverse;
      bool invertible = false;
      block.computeInverseWithCheck(inverse, invertible);
      if (!invertible || !inverse.allFinite()) {
        part.invertible = false;
        return part;
      }
      for (int k = 0; k < 9; ++k) {
        diagonal_[9 * static_cast<std::size_t>(c) + static_cast<std::size_t>(k)] =
            block(k / 3, k % 3);
        inverse_[9 * static_cast<std::size_t>(c) + static_cast<std::size_t>(k)] =
            inverse(k / 3, k % 3);
      }
    }
    return part;
  });
  coarse_ = total.coarse;
  return total.invertible;
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
  if (!load_columns(a)) {
    x.setConstant(std::numeric_limits<double>::quiet_NaN());
    report.succeeded = false;
    report.residual = std::numeric_limits<double>::quiet_NaN();
    return report;
  }
  EnergyErrorEstimate estimate(
      reference_energy(a, x, offset, energy_floor(), direction_, chunk_sums_));
  // r0 = b - A x0, with the caller's product when it has one.
  const double* ax = start_product(a, x, known_product, product_).data();

  const double* d = diagonal_.data();
  const double* inverse = inverse_.data();
  const double* bs = b.data();
  double* xs = x.data();
  double* x_hat = transformed_.data();
  double* r = residual_.data();
  double* z = preconditioned_.data();
  double* p = direction_.data();
  double* q = product_.data();
  double* t = sweep_.data();
  double* g = carry_.data();

  // The sweeps run over the pattern's parts side by side (no block joins two of them) and over
  // the separator alone: after the parts forward, before them backward, as a vertex's
  // predecessors in its sweep are then done. One part: the sweeps in vertex order.
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

  // CG on the correction x - x0 from 0: its transform x^ = (D + U) (x - x0) starts at 0, and
  // r^ = (D + L)^-1 r0 (a forward sweep, into g). And the scale of round-off for the
  // transformed residual: |D^-1 b|, the transformed right-hand side's size up to the coupling of
  // the sweep (a floor at 1e-14 of it needs no more).
  const double transformed_rhs_squared =
      forward([&](int first, int last) {
        RangeSums part;
        for (int c = first; c < last; ++c) {
          double lower[3];
          a.neighbour_sum(c, /*lower=*/true, g, lower);
          const double rest[3] = {bs[3 * c] - ax[3 * c] - lower[0],
                                  bs[3 * c + 1] - ax[3 * c + 1] - lower[1],
                                  bs[3 * c + 2] - ax[3 * c + 2] - lower[2]};
          block_multiply(inverse + 9 * c, rest, g + 3 * c);
          double scaled[3];
          block_multiply(inverse + 9 * c, bs + 3 * c, scaled);
          part.first += dot3(scaled, scaled);
        }
        return part;
      }).first;
  transformed_.setZero();
  const auto apply_d = [d](int c, const double* in, double* out) {
    block_multiply(d + 9 * c, in, out);
  };
  const EisenstatStart start = eisenstat_start(ranges, g, x_hat, r, z, p, apply_d);
  const double roundoff = kRoundoff * std::sqrt(transformed_rhs_squared);

  report.converged = start.residual_squared == 0.0;
  const auto sweeps = [&](double beta) {
    // Backward: p = z + beta p, t = (D + U)^-1 p, and g = p - D t, which is U t.
    backward([&](int first, int last) {
      for (int c = last - 1; c >= first; --c) {
        double pc[3];
        for (int k = 0; k < 3; ++k) {
          pc[k] = z[3 * c + k] + beta * p[3 * c + k];
          p[3 * c + k] = pc[k];
        }
        double upper[3];
        a.neighbour_sum(c, /*lower=*/false, t, upper);
        const double rest[3] = {pc[0] - upper[0], pc[1] - upper[1], pc[2] - upper[2]};
        block_multiply(inverse + 9 * c, rest, t + 3 * c);
        g[3 * c] = upper[0];
        g[3 * c + 1] = upper[1];
        g[3 * c + 2] = upper[2];
      }
      return RangeSums{};
    });
    // Forward: y = (D + L)^-1 g (into g), q = A^ p = t + y, and p . q.
    return forward([&](int first, int last) {
             RangeSums part;
             for (int c = first; c < last; ++c) {
               double lower[3];
               a.neighbour_sum(c, /*lower=*/true, g, lower);
               const double rest[3] = {g[3 * c] - lower[0], g[3 * c + 1] - lower[1],
                                       g[3 * c + 2] - lower[2]};
               double y[3];
               block_multiply(inverse + 9 * c, rest, y);
               g[3 * c] = y[0];
               g[3 * c + 1] = y[1];
               g[3 * c + 2] = y[2];
               const double qc[3] = {t[3 * c] + y[0], t[3 * c + 1] + y[1], t[3 * c + 2] + y[2]};
               q[3 * c] = qc[0];
               q[3 * c + 1] = qc[1];
               q[3 * c + 2] = qc[2];
               part.first += dot3(p + 3 * c, qc);
             }
             return part;
           })
        .first;
  };
  eisenstat_iterations(ranges, x_hat, r, z, p, q, start.rz, roundoff, options_.tolerance,
                       options_.max_iterations, estimate, report, sweeps, apply_d);

  // x = x0 + (D + U)^-1 x^ ...
  backward([&](int first, int last) {
    for (int c = last - 1; c >= first; --c) {
      double upper[3];
      a.neighbour_sum(c, /*lower=*/false, t, upper);
      const double rest[3] = {x_hat[3 * c] - upper[0], x_hat[3 * c + 1] - upper[1],
                              x_hat[3 * c + 2] - upper[2]};
      block_multiply(inverse + 9 * c, rest, t + 3 * c);
      for (int k = 0; k < 3; ++k) {
        xs[3 * c + k] += t[3 * c + k];
      }
    }
    return RangeSums{};
  });
  // ... the system's residual b - A x = (D + L) r^ (into q; r^ is not written, so every range
  // at once) ...
  over_ranges(ranges, [&](int first, int last) {
    for (int c = first; c < last; ++c) {
      double lower[3];
      a.neighbour_sum(c, /*lower=*/true, r, lower);
      double own[3];
      block_multiply(d + 9 * c, r + 3 * c, own);
      for (int k = 0; k < 3; ++k) {
        q[3 * c + k] = own[k] + lower[k];
      }
    }
    return RangeSums{};
  });
  Eigen::Vector3d residual_sum = Eigen::Vector3d::Zero();
  for (int c = 0; c < n; ++c) {
    for (int k = 0; k < 3; ++k) {
      residual_sum(k) += q[3 * c + k];
    }
  }
  // ... and the coarse correction on the rigid translations Z (x += Z c with Z^T A Z c =
  // Z^T r, the A-orthogonal projection: it never increases the error's energy norm). Stiffness
  // does not resist a translation, so the sweeps' smoothing leaves its error nearly untouched:
  // without it a free body thrown across the scene drifted 1e-6 of its travel from its
  // momentum balance in 1 s at the default tolerance; with it, round-off.
  const Eigen::Vector3d shift = coarse_.ldlt().solve(residual_sum);
  double true_squared = 0.0;
  if (shift.allFinite() && shift.squaredNorm() > 0.0) {
    for (int c = 0; c < n; ++c) {
      const Eigen::Map<const Eigen::Matrix3d> sums(row_sums_.data() + 9 * c);  // (A Z)_c^T
      const Eigen::Vector3d moved = sums.transpose() * shift;
      for (int k = 0; k < 3; ++k) {
        xs[3 * c + k] += shift(k);
        q[3 * c + k] -= moved(k);
      }
    }
  }
  for (int c = 0; c < n; ++c) {
    true_squared += dot3(q + 3 * c, q + 3 * c);
  }
  report.residual = std::sqrt(true_squared) / rhs_norm;
  report.succeeded = std::isfinite(report.residual) && x.allFinite();
  return report;
}

std::size_t SsorConjugateGradientSolver::memory_bytes() const {
  return (diagonal_.capacity() + inverse_.capacity() + row_sums_.capacity()
          + chunk_sums_.capacity())
             * sizeof(double)
         + 7 * static_cast<std::size_t>(residual_.size()) * sizeof(double);
}

}  // namespace softbench
