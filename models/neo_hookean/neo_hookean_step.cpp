// SPDX-License-Identifier: MIT
// One step of the neo-Hookean reference: Newton's method with a backtracking line search on the
// incremental potential, a CHOLMOD solve per iteration, exact constraints by elimination.
#include "models/finite_state.h"
#include "models/memory_bytes.h"
#include "models/neo_hookean/neo_hookean_model.h"

#include <algorithm>
#include <cmath>
#include <limits>

namespace softbench::neo_hookean {
namespace {

/// Element loops over fewer elements run on one thread, as corotational_fem's do (see
/// corotational_fem_step.cpp: on this 2-core machine a parallel region waits for a descheduled
/// thread whenever another job holds a core). The shipped liver (4777 tets) runs serially.
constexpr int kParallelElements = 16384;

/// The relative round-off of the incremental potential, a sum of a few thousand terms (each
/// ~1e-16 of its magnitude): sqrt(#terms) x 1e-16 for a 1e4-term sum, with a 100x margin.
constexpr double kEnergyRoundoff = 1e-12;

}  // namespace

void NeoHookeanModel::evaluate_elements(const Eigen::Matrix3Xd& x, Derivatives derivatives) {
#pragma omp parallel for schedule(static) if (num_elements_ > kParallelElements)
  for (int t = 0; t < num_elements_; ++t) {
    const auto e = static_cast<std::size_t>(t);
    const TetRest& rest = elements_[e];
    const Eigen::Matrix3d deformation = deformation_gradient(rest, tet_positions(x, tets_, t));
    element_energies_[e] = rest.volume * energy_density(deformation, law_);
    if (derivatives == Derivatives::kNone) {
      continue;
    }
    element_gradients_[e] = element_gradient(rest, first_piola(deformation, law_));
    if (derivatives == Derivatives::kGradient) {
      continue;
    }
    element_hessians_[e] =
        element_hessian(rest, derivatives == Derivatives::kGradientAndProjectedHessian
                                  ? projected_stress_derivative(deformation, law_)
                                  : stress_derivative(deformation, law_));
  }
}

NeoHookeanModel::EnergyValue NeoHookeanModel::potential_energy(const Potential& potential,
                                                               const Eigen::Matrix3Xd& x) const {
  double energy = 0.0;
  double magnitude = 0.0;
  for (const double element : element_energies_) {
    energy += element;
    magnitude += std::abs(element);
  }
  const StepInput& input = *potential.input;
  const double dt = potential.dt;
  const double inertia = 0.5 / (dt * dt);
  const double damping = 0.5 * params_.rayleigh_mass / dt;
  for (int v = 0; v < num_vertices_; ++v) {
    const double mass = masses_(v);
    const Eigen::Vector3d displacement = x.col(v) - previous_.col(v);
    // Measured from x_n, not the origin: the same potential up to a constant, without the
    // round-off of large absolute coordinates in the line search's comparisons.
    Eigen::Vector3d load = mass * input.gravity;
    if (input.external_forces != nullptr) {
      load += input.external_forces->col(v);
    }
    const double kinetic = mass
                           * (inertia * (x.col(v) - predicted_.col(v)).squaredNorm()
                              + damping * displacement.squaredNorm());
    const double work = load.dot(displacement);
    energy += kinetic - work;
    magnitude += kinetic + std::abs(work);
    const PositionConstraint* constraint = constraints_.of(v);
    if (is_penalty(constraint)) {
      const double spring = 0.5 * constraint->stiffness * constraint->gap(x.col(v)).squaredNorm();
      energy += spring;
      magnitude += spring;
    }
  }
  return {energy, magnitude};
}

void NeoHookeanModel::assemble_gradient(const Potential& potential, const Eigen::Matrix3Xd& x) {
  gradient_.setZero();
  for (int t = 0; t < num_elements_; ++t) {
    const Matrix34d& element = element_gradients_[static_cast<std::size_t>(t)];
    for (int a = 0; a < 4; ++a) {
      gradient_.col(tets_(a, t)) += element.col(a);
    }
  }
  const StepInput& input = *potential.input;
  const double dt = potential.dt;
  const double damping = params_.rayleigh_mass / dt;
  for (int v = 0; v < num_vertices_; ++v) {
    const double mass = masses_(v);
    Eigen::Vector3d term = mass
                           * ((x.col(v) - predicted_.col(v)) / (dt * dt)
                              + damping * (x.col(v) - previous_.col(v)) - input.gravity);
    if (input.external_forces != nullptr) {
      term -= input.external_forces->col(v);
    }
    const PositionConstraint* constraint = constraints_.of(v);
    if (is_penalty(constraint)) {
      term -= constraint->stiffness * constraint->gap(x.col(v));
    }
    gradient_.col(v) += term;
  }
}

void NeoHookeanModel::assemble_hessian(const Potential& potential) {
  Eigen::SparseMatrix<double>& matrix = pattern_->matrix();
  std::fill(matrix.valuePtr(), matrix.valuePtr() + matrix.nonZeros(), 0.0);
  double* values = matrix.valuePtr();
  for (int t = 0; t < num_elements_; ++t) {
    const Matrix12d& hessian = element_hessians_[static_cast<std::size_t>(t)];
    const BlockEntries* blocks = element_blocks_.data() + 16 * static_cast<std::ptrdiff_t>(t);
    for (int a = 0; a < 4; ++a) {
      for (int b = 0; b < 4; ++b) {
        const BlockEntries& where = blocks[4 * a + b];
        for (int r = 0; r < 3; ++r) {
          for (int c = 0; c < 3; ++c) {
            values[where[static_cast<std::size_t>(3 * r + c)]] += hessian(3 * a + r, 3 * b + c);
          }
        }
      }
    }
  }
  for (int v = 0; v < num_vertices_; ++v) {
    Eigen::Matrix3d block = potential.mass_coefficient * masses_(v) * Eigen::Matrix3d::Identity();
    const PositionConstraint* constraint = constraints_.of(v);
    if (is_penalty(constraint)) {
      block += constraint->stiffness * constraint->held;
    }
    const BlockEntries& where = pattern_->vertex_block(v);
    for (int a = 0; a < 3; ++a) {
      for (int b = 0; b < 3; ++b) {
        values[where[static_cast<std::size_t>(3 * a + b)]] += block(a, b);
      }
    }
  }
}

StepStats NeoHookeanModel::step(double dt, const StepInput& input) {
  constraints_.bind(input.constraints);
  Potential potential;
  potential.dt = dt;
  potential.mass_coefficient = 1.0 / (dt * dt) + params_.rayleigh_mass / dt;
  potential.input = &input;

  previous_ = positions_;
  predicted_ = positions_ + dt * velocities_;
  positions_ = predicted_;
  for (const int c : constraints_.exact_vertices()) {
    if (const PositionConstraint* constraint = constraints_.of(c); constraint != nullptr) {
      positions_.col(c) = constraint->place(positions_.col(c));
    }
  }

  StepStats stats;
  const double converged_step = params_.tolerance * length_scale_;
  double step_norm = std::numeric_limits<double>::infinity();
  bool project = params_.projection == NeoHookeanParams::Projection::kAlways;
  while (stats.iterations < params_.max_iterations) {
    ++stats.iterations;
    evaluate_elements(positions_, project ? Derivatives::kGradientAndProjectedHessian
                                          : Derivatives::kGradientAndHessian);
    const EnergyValue energy = potential_energy(potential, positions_);
    assemble_gradient(potential, positions_);
    assemble_hessian(potential);
    rhs_ = -Eigen::Map<const Eigen::VectorXd>(gradient_.data(), pattern_->size());
    elimination_.eliminate(*pattern_, constraints_, zero_change_, rhs_, newton_step_);
    SolveReport report = solver_->solve(*pattern_, rhs_, newton_step_, nullptr);
    elimination_.to_world(newton_step_);
    stats.factorizations += report.factorizations;
    ++stats.linear_solves;
    if (!report.succeeded && !project && std::isfinite(energy.value)) {
      // The exact Hessian is not positive definite here: project from now on in this step.
      project = true;
      evaluate_elements(positions_, Derivatives::kGradientAndProjectedHessian);
      assemble_hessian(potential);
      elimination_.eliminate(*pattern_, constraints_, zero_change_, rhs_, newton_step_);
      report = solver_->solve(*pattern_, rhs_, newton_step_, nullptr);
      elimination_.to_world(newton_step_);
      stats.factorizations += report.factorizations;
      ++stats.linear_solves;
    }
    if (!report.succeeded) {
      stats.finite = false;
      break;
    }
    Eigen::Map<Eigen::Matrix3Xd> change(newton_step_.data(), 3, num_vertices_);
    for (const int c : constraints_.exact_vertices()) {
      // Exactly on the target (a sliding vertex on its plane), whatever the solve's round-off.
      if (const PositionConstraint* constraint = constraints_.of(c); constraint != nullptr) {
        change.col(c) -= constraint->held * change.col(c);
      }
    }
    step_norm = change.colwise().norm().maxCoeff();
    if (!std::isfinite(step_norm)) {
      stats.finite = false;
      break;
    }
    if (step_norm <= converged_step) {
      positions_ += change;
      break;
    }

    // Backtracking (Armijo) along dx; the projected Hessian makes dx a descent direction. The
    // test allows E's round-off (kEnergyRoundoff of its terms' magnitudes): near convergence
    // the decrease falls below it and only the round-off would decide.
    const double descent =
        Eigen::Map<const Eigen::VectorXd>(gradient_.data(), pattern_->size()).dot(newton_step_);
    const double slack = kEnergyRoundoff * energy.magnitude;
    bool accepted = false;
    double length = 1.0;
    for (int backtrack = 0; backtrack <= params_.max_backtracks && descent < 0.0; ++backtrack) {
      trial_ = positions_ + length * change;
      evaluate_elements(trial_, Derivatives::kNone);
      const double trial_energy = potential_energy(potential, trial_).value;
      if (trial_energy <= energy.value + params_.armijo * length * descent + slack) {
        accepted = true;
        break;
      }
      length *= params_.backtrack;
    }
    if (!accepted) {
      break;  // no decrease along the Newton step: reported through the residual
    }
    positions_.swap(trial_);
  }
  stats.residual = step_norm / length_scale_;
  stats.truncated_solves = stats.finite && !(step_norm <= converged_step) ? 1 : 0;

  velocities_ = (positions_ - previous_) / dt;
  constraint_forces_.setZero();
  if (!constraints_.vertices().empty()) {
    // Reactions from the potential's gradient at the final positions.
    evaluate_elements(positions_, Derivatives::kGradient);
    assemble_gradient(potential, positions_);
    for (const int v : constraints_.vertices()) {
      const PositionConstraint* constraint = constraints_.of(v);
      if (constraint == nullptr) {
        continue;  // not reached: every listed vertex has one
      }
      if (is_exact(constraint)) {
        // Along the held directions: a sliding vertex's tangential balance is the solve's.
        constraint_forces_.col(v) = constraint->held * gradient_.col(v);
      } else {
        constraint_forces_.col(v) = constraint->stiffness * constraint->gap(positions_.col(v));
        stats.max_constraint_error =
            std::max(stats.max_constraint_error, constraint->gap(positions_.col(v)).norm());
      }
    }
  }
  constraints_.unbind();
  stats.finite = stats.finite && state_finite(positions_, velocities_);
  return stats;
}

}  // namespace softbench::neo_hookean
