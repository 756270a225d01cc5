// SPDX-License-Identifier: MIT
#include "models/system_solver.h"

#include "models/cholmod_factor.h"
#include "models/ssor_solver.h"
#include "models/warm_start.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <limits>
#include <span>
#include <utility>
#include <vector>

namespace softbench {
namespace {

using SparseMatrix = Eigen::SparseMatrix<double>;

double relative(double residual_norm, double rhs_norm) {
  return rhs_norm > 0.0 ? residual_norm / rhs_norm : residual_norm;
}

/// The vector loops of PCG over the fixed chunks of BlockPattern, so every dot product is summed
/// in the same order whatever the thread count (bit-identical results on 1 and 2 threads).
class ChunkedVectors {
 public:
  explicit ChunkedVectors(const BlockPattern& pattern)
      : num_vertices_(pattern.num_vertices()),
        threaded_(pattern.threaded()),
        chunk_sums_(static_cast<std::size_t>(pattern.num_chunks()), 0.0) {}

  std::span<double> chunk_sums() { return chunk_sums_; }
  double total() const {
    double sum = 0.0;
    for (const double part : chunk_sums_) {
      sum += part;
    }
    return sum;
  }

  /// Applies `body(begin, end)` to the entry ranges of each chunk, in parallel when the pattern
  /// is (BlockPattern::threaded(), as its products), and returns the ordered sum of what each
  /// call returns.
  template <class Body>
  double for_each_chunk(const Body& body) {
    const auto chunks = static_cast<int>(chunk_sums_.size());
    const Eigen::Index entries = 3 * static_cast<Eigen::Index>(num_vertices_);
#pragma omp parallel for schedule(static) if (threaded_)
    for (int chunk = 0; chunk < chunks; ++chunk) {
      const Eigen::Index begin =
          3 * static_cast<Eigen::Index>(chunk) * BlockPattern::kChunkVertices;
      const Eigen::Index end =
          std::min(entries, begin + 3 * static_cast<Eigen::Index>(BlockPattern::kChunkVertices));
      chunk_sums_[static_cast<std::size_t>(chunk)] = body(begin, end);
    }
    return total();
  }

  std::size_t memory_bytes() const {
    return chunk_sums_.capacity() * sizeof(double);
  }

 private:
  int num_vertices_;
  bool threaded_;  ///< the pattern's, when the solver was made (its parts are set before)
  std::vector<double> chunk_sums_;
};

/// Preconditioned CG on preallocated vectors (Eigen's ConjugateGradient allocates its work
/// vectors on every solve), stopped by the estimated energy-norm error (LinearSolverOptions::
/// tolerance). The reported residual is the recursively updated one, relative to |b|.
class PcgIterations {
 public:
  /// Iterations the error estimate sums over: its delay (EnergyErrorEstimate).
  static constexpr int kErrorDelay = EnergyErrorEstimate::kDelay;

  explicit PcgIterations(const BlockPattern& pattern)
      : vectors_(pattern),
        residual_(pattern.size()),
        preconditioned_(pattern.size()),
        direction_(pattern.size()),
        product_(pattern.size()) {}

  /// `precondition(r, z)` sets z = M^-1 r. Returns the iterations, |r| / |b| and the estimated
  /// relative error.
  template <class Preconditioner>
  SolveReport run(const BlockPattern& a,
                  const Eigen::VectorXd& b,
                  Eigen::VectorXd& x,
                  const double* offset,
                  double energy_floor,
                  const Eigen::VectorXd* known_product,
                  double tolerance,
                  int max_iterations,
                  const Preconditioner& precondition) {
    SolveReport report;
    double* r = residual_.data();
    double* z = preconditioned_.data();
    double* p = direction_.data();
    double* q = product_.data();
    double* xs = x.data();
    const double* bs = b.data();

    const double rhs_norm =
        std::sqrt(vectors_.for_each_chunk([bs](Eigen::Index begin, Eigen::Index end) {
          double sum = 0.0;
          for (Eigen::Index i = begin; i < end; ++i) {
            sum += bs[i] * bs[i];
          }
          return sum;
        }));
    if (rhs_norm == 0.0) {
      x.setZero();
      return report;
    }
    EnergyErrorEstimate estimate(
        reference_energy(a, x, offset, energy_floor, direction_, vectors_.chunk_sums()));

    const double* ax = start_product(a, x, known_product, product_).data();
    double residual_norm =
        std::sqrt(vectors_.for_each_chunk([r, bs, ax](Eigen::Index begin, Eigen::Index end) {
          double sum = 0.0;
          for (Eigen::Index i = begin; i < end; ++i) {
            r[i] = bs[i] - ax[i];
            sum += r[i] * r[i];
          }
          return sum;
        }));
    report.converged = residual_norm == 0.0;
    if (!report.converged) {
      precondition(residual_, preconditioned_);
      double rz = vectors_.for_each_chunk([r, z, p](Eigen::Index begin, Eigen::Index end) {
        double sum = 0.0;
        for (Eigen::Index i = begin; i < end; ++i) {
          p[i] = z[i];
          sum += r[i] * z[i];
        }
        return sum;
      });
      while (report.iterations < max_iterations) {
        ++report.iterations;
        a.multiply(direction_, product_, vectors_.chunk_sums());
        const double curvature = vectors_.total();
        if (!(curvature > 0.0) || !std::isfinite(rz)) {
          break;  // not positive definite, or NaN: stop with what we have
        }
        const double alpha = rz / curvature;
        report.error = estimate.add(report.iterations, alpha * rz);
        residual_norm = std::sqrt(
            vectors_.for_each_chunk([alpha, xs, r, p, q](Eigen::Index begin, Eigen::Index end) {
              double sum = 0.0;
              for (Eigen::Index i = begin; i < end; ++i) {
                xs[i] += alpha * p[i];
                r[i] -= alpha * q[i];
                sum += r[i] * r[i];
              }
              return sum;
            }));
        // Converged, or at round-off: a residual this small leaves nothing to gain (an exact
        // preconditioner gets there in one iteration, before the estimate has its window).
        constexpr double kRoundoff = 1e-14;
        if (residual_norm <= kRoundoff * rhs_norm || estimate.met(report.iterations, tolerance)) {
          report.converged = true;
          break;
        }
        precondition(residual_, preconditioned_);
        const double rz_next =
            vectors_.for_each_chunk([r, z](Eigen::Index begin, Eigen::Index end) {
              double sum = 0.0;
              for (Eigen::Index i = begin; i < end; ++i) {
                sum += r[i] * z[i];
              }
              return sum;
            });
        const double beta = rz_next / rz;
        rz = rz_next;
        vectors_.for_each_chunk([beta, z, p](Eigen::Index begin, Eigen::Index end) {
          for (Eigen::Index i = begin; i < end; ++i) {
            p[i] = z[i] + beta * p[i];
          }
          return 0.0;
        });
      }
    }
    report.residual = relative(residual_norm, rhs_norm);
    report.succeeded = std::isfinite(residual_norm);
    return report;
  }

  std::size_t memory_bytes() const {
    return 4 * static_cast<std::size_t>(residual_.size()) * sizeof(double)
           + vectors_.memory_bytes();
  }

 private:
  ChunkedVectors vectors_;
  Eigen::VectorXd residual_;
  Eigen::VectorXd preconditioned_;
  Eigen::VectorXd direction_;
  Eigen::VectorXd product_;
};

/// A fresh numeric factorisation every step (the values change), on the one symbolic analysis.
class CholmodSolver final : public SystemSolver {
 public:
  explicit CholmodSolver(const BlockPattern& pattern)
      : factor_(pattern.matrix(), /*supernodal=*/true), product_(pattern.size()) {}

  SolveReport solve(const BlockPattern& a,
                    const Eigen::VectorXd& b,
                    Eigen::VectorXd& x,
                    const double* /*offset: an exact solve needs none*/) override {
    SolveReport report;
    report.factorizations = 1;
    if (!factor_.factorize(a.matrix())) {
      x.setConstant(std::numeric_limits<double>::quiet_NaN());
      report.succeeded = false;
      report.residual = std::numeric_limits<double>::quiet_NaN();
      return report;
    }
    factor_.solve(b, x);
    a.multiply(x, product_);
    report.residual = relative((product_ - b).norm(), b.norm());
    report.succeeded = std::isfinite(report.residual);
    return report;
  }

  std::size_t memory_bytes() const override {
    return factor_.memory_bytes() + static_cast<std::size_t>(product_.size()) * sizeof(double);
  }

 private:
  CholmodFactor factor_;
  Eigen::VectorXd product_;
};

/// Jacobi-preconditioned CG, warm-started from the caller's guess.
class ConjugateGradientSolver final : public SystemSolver {
 public:
  ConjugateGradientSolver(const LinearSolverOptions& options, const BlockPattern& pattern)
      : options_(options), iterations_(pattern), inverse_diagonal_(pattern.size()) {}

  SolveReport solve(const BlockPattern& a,
                    const Eigen::VectorXd& b,
                    Eigen::VectorXd& x,
                    const double* offset) override {
    const double* values = a.matrix().valuePtr();
    for (int v = 0; v < a.num_vertices(); ++v) {
      const BlockEntries& diagonal = a.vertex_block(v);
      for (int k = 0; k < 3; ++k) {
        const double entry = values[diagonal[static_cast<std::size_t>(4 * k)]];
        // Eigen's DiagonalPreconditioner: 1 where the diagonal is zero.
        inverse_diagonal_(3 * v + k) = entry != 0.0 ? 1.0 / entry : 1.0;
      }
    }
    return iterations_.run(a, b, x, offset, energy_floor(), take_start_product(),
                           options_.tolerance, options_.max_iterations,
                           [this](const Eigen::VectorXd& r, Eigen::VectorXd& z) {
                             z = inverse_diagonal_.cwiseProduct(r);
                           });
  }

  std::size_t memory_bytes() const override {
    return iterations_.memory_bytes()
           + static_cast<std::size_t>(inverse_diagonal_.size()) * sizeof(double);
  }

 private:
  LinearSolverOptions options_;
  PcgIterations iterations_;
  Eigen::VectorXd inverse_diagonal_;
};

/// CG preconditioned by the Cholesky factor of an earlier step's matrix (in the spirit of Hecht
/// et al. 2012, who update a factor selectively instead of refactorising): the factor is kept
/// while the iterations it needs stay at or below refresh_iterations, and replaced by the
/// current matrix's when they exceed it. A solve that fails to converge with a stale factor is
/// redone with a fresh one, so the cap bounds the work but not the accuracy.
class CholeskyPcgSolver final : public SystemSolver {
 public:
  CholeskyPcgSolver(const LinearSolverOptions& options, const BlockPattern& pattern)
      : options_(options), factor_(pattern.matrix(), /*supernodal=*/true), iterations_(pattern) {}

  SolveReport solve(const BlockPattern& a,
                    const Eigen::VectorXd& b,
                    Eigen::VectorXd& x,
                    const double* offset) override {
    const Eigen::VectorXd* known_product = take_start_product();
    int factorizations = 0;
    if (stale_) {
      if (!refactorize(a)) {
        return failed(x);
      }
      ++factorizations;
    }
    const auto precondition = [this](const Eigen::VectorXd& r, Eigen::VectorXd& z) {
      factor_.solve(r, z);
    };
    SolveReport report = iterations_.run(a, b, x, offset, energy_floor(), known_product,
                                         options_.tolerance, options_.max_iterations, precondition);
    if (!report.converged && factorizations == 0) {
      // The old factor no longer preconditions this matrix: refactorise and continue from x.
      if (!refactorize(a)) {
        return failed(x);
      }
      ++factorizations;
      const int spent = report.iterations;
      report = iterations_.run(a, b, x, offset, energy_floor(), nullptr, options_.tolerance,
                               options_.max_iterations, precondition);
      report.iterations += spent;
    }
    // The estimate's window (PcgIterations::kErrorDelay) is the stopping rule's cost, not the
    // preconditioner's: it does not count against the factor.
    stale_ = report.iterations - PcgIterations::kErrorDelay > options_.refresh_iterations;
    report.factorizations = factorizations;
    return report;
  }

  std::size_t memory_bytes() const override {
    return factor_.memory_bytes() + iterations_.memory_bytes();
  }

 private:
  bool refactorize(const BlockPattern& a) {
    stale_ = false;
    return factor_.factorize(a.matrix());
  }
  SolveReport failed(Eigen::VectorXd& x) {
    stale_ = true;
    x.setConstant(std::numeric_limits<double>::quiet_NaN());
    SolveReport report;
    report.factorizations = 1;
    report.succeeded = false;
    report.residual = std::numeric_limits<double>::quiet_NaN();
    return report;
  }

  LinearSolverOptions options_;
  CholmodFactor factor_;
  PcgIterations iterations_;
  bool stale_ = true;  ///< no factor yet, or the last solve needed too many iterations
};

/// An iterative solver started from GalerkinWarmStart's guess, which remembers its solutions.
class ProjectedWarmStartSolver final : public SystemSolver {
  static_assert(GalerkinWarmStart::kBasis <= BlockPattern::kManyVectors);

 public:
  ProjectedWarmStartSolver(std::unique_ptr<SystemSolver> inner, const BlockPattern& pattern)
      : inner_(std::move(inner)), warm_start_(pattern.size()) {}

  SolveReport solve(const BlockPattern& a,
                    const Eigen::VectorXd& b,
                    Eigen::VectorXd& x,
                    const double* offset) override {
    inner_->set_start_product(warm_start_.improve(
        b, x,
        [&a](std::span<const Eigen::VectorXd* const> in, std::span<Eigen::VectorXd* const> out) {
          a.multiply_many(in, out);
        }));
    inner_->set_energy_floor(energy_floor());
    const SolveReport report = inner_->solve(a, b, x, offset);
    if (report.succeeded) {
      warm_start_.remember(x);
    } else {
      warm_start_.forget();
    }
    return report;
  }
  std::size_t memory_bytes() const override {
    return inner_->memory_bytes() + warm_start_.memory_bytes();
  }
  void forget() override {
    inner_->forget();
    warm_start_.forget();
  }

 private:
  std::unique_ptr<SystemSolver> inner_;
  GalerkinWarmStart warm_start_;
};

std::unique_ptr<SystemSolver> make_iterative_solver(const LinearSolverOptions& options,
                                                    const BlockPattern& pattern) {
  switch (options.kind) {
    case LinearSolverOptions::Kind::kCholeskyPcg:
      return std::make_unique<CholeskyPcgSolver>(options, pattern);
    case LinearSolverOptions::Kind::kConjugateGradient:
    case LinearSolverOptions::Kind::kCholmod:
      break;
  }
  if (options.preconditioner == LinearSolverOptions::Preconditioner::kSsor) {
    return std::make_unique<SsorConjugateGradientSolver>(options, pattern);
  }
  return std::make_unique<ConjugateGradientSolver>(options, pattern);
}

}  // namespace

double reference_energy(const BlockPattern& a,
                        const Eigen::VectorXd& x,
                        const double* offset,
                        double floor,
                        Eigen::VectorXd& work,
                        std::span<double> chunk_sums) {
  double energy = 0.0;
  if (offset != nullptr) {
    work = Eigen::Map<const Eigen::VectorXd>(offset, x.size()) + x;
    energy = std::max(0.0, a.quadratic_form(work, chunk_sums));
  }
  return std::max(energy, floor);
}

std::unique_ptr<SystemSolver> make_system_solver(const LinearSolverOptions& options,
                                                 const BlockPattern& pattern) {
  if (options.kind == LinearSolverOptions::Kind::kCholmod) {
    return std::make_unique<CholmodSolver>(pattern);
  }
  std::unique_ptr<SystemSolver> solver = make_iterative_solver(options, pattern);
  if (options.projected_warm_start) {
    return std::make_unique<ProjectedWarmStartSolver>(std::move(solver), pattern);
  }
  return solver;
}

}  // namespace softbench
