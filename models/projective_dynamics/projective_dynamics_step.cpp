// SPDX-License-Identifier: MIT
// One Projective Dynamics step: the factor kept or renewed, the inertial prediction, then
// local (rotations, projections) and global (three triangular solve pairs, the holds'
// multipliers) iterations, and the update with the holds' forces.
#include "models/corotational_fem/polar_decomposition.h"
#include "models/finite_state.h"
#include "models/projective_dynamics/projective_dynamics_model.h"

#include <omp.h>

#include <algorithm>
#include <cmath>
#include <cstddef>
#include <span>

namespace softbench::projective_dynamics {
namespace {

/// The rotation extraction's stopping size (rad); the iterations refine R further each step.
constexpr double kRotationTolerance = 1e-6;

}  // namespace

bool ProjectiveDynamicsModel::update_factor(double dt, int* factorizations) {
  const bool same_set = std::equal(wanted_.begin(), wanted_.end(), eliminated_.begin());
  if (dt == factored_dt_ && same_set) {
    return true;
  }
  eliminated_ = wanted_;
  eliminated_list_.clear();
  for (int v = 0; v < num_vertices_; ++v) {
    if (eliminated_[static_cast<std::size_t>(v)] != 0) {
      eliminated_list_.push_back(v);
    }
  }
  eliminated_gradients_.resize(3, static_cast<Eigen::Index>(eliminated_list_.size()));
  mass_coefficient_ = 1.0 / (dt * dt) + params_.rayleigh_mass / dt;
  // A = M (1/dt^2 + alpha/dt) + L, with an eliminated vertex's row and column the identity's.
  double* values = system_.valuePtr();
  const double* laplacian = laplacian_.valuePtr();
  for (int column = 0; column < num_vertices_; ++column) {
    const bool column_out = eliminated_[static_cast<std::size_t>(column)] != 0;
    for (int k = system_.outerIndexPtr()[column]; k < system_.outerIndexPtr()[column + 1]; ++k) {
      const int row = system_.innerIndexPtr()[k];
      const bool out = column_out || eliminated_[static_cast<std::size_t>(row)] != 0;
      if (row == column) {
        values[k] = column_out ? 1.0 : laplacian[k] + mass_coefficient_ * masses_(row);
      } else {
        values[k] = out ? 0.0 : laplacian[k];
      }
    }
  }
  held_rows_.forget();
  factored_dt_ = 0.0;
  ++*factorizations;
  if (!factor_->factorize(system_)) {
    return false;
  }
  factored_dt_ = dt;
  return true;
}

void ProjectiveDynamicsModel::project_elements(const Eigen::Matrix3Xd& x) {
  constexpr int kBlock = 64;
  const int num_blocks = (num_elements_ + kBlock - 1) / kBlock;
  const double shear_weight = 2.0 * lame_.mu;       // w_s / V
  const double volume_weight = 3.0 * lame_.lambda;  // w_v / V
  // One thread: each element's parts are added to its vertices as soon as they are made (in
  // element order). More: made in parallel into per-element storage, then gathered per vertex
  // in the same element order, so the sums, and the results, do not depend on the threads.
  const bool parallel = !element_parts_.empty() && omp_get_max_threads() > 1;
  element_sums_.setZero();
#pragma omp parallel for schedule(static) if (parallel)
  for (int block = 0; block < num_blocks; ++block) {
    const int first = block * kBlock;
    const int last = std::min(num_elements_, first + kBlock);
    for (int t = first; t < last; ++t) {
      deformations_[static_cast<std::size_t>(t)] =
          deformation_gradient(elements_[static_cast<std::size_t>(t)], tet_positions(x, tets_, t));
    }
    const auto begin = static_cast<std::size_t>(first);
    const auto count = static_cast<std::size_t>(last - first);
    corotational_fem::extract_rotations(std::span(deformations_).subspan(begin, count),
                                        std::span(quaternions_).subspan(begin, count),
                                        std::span(rotations_).subspan(begin, count),
                                        params_.rotation_iterations, kRotationTolerance);
    for (int t = first; t < last; ++t) {
      const auto e = static_cast<std::size_t>(t);
      const Eigen::Matrix3d& f = deformations_[e];
      const Eigen::Matrix3d& r = rotations_[e];
      // The constraints' gradient w_s (F - R) + w_v c R (c = (tr(R^T F) - 3) / 3), i.e. w F
      // less the projections' targets: small near rest, so no large terms cancel in b - A x.
      const double c = (r.cwiseProduct(f).sum() - 3.0) / 3.0;
      const Eigen::Matrix3d gradient =
          elements_[e].volume * (shear_weight * (f - r) + (volume_weight * c) * r);
      Matrix34d parts;
      parts.rightCols<3>().noalias() = gradient * elements_[e].rest_inverse.transpose();
      parts.col(0) = -parts.rightCols<3>().rowwise().sum();
      if (parallel) {
        element_parts_[e] = parts;
      } else {
        for (int a = 0; a < 4; ++a) {
          element_sums_.col(tets_(a, t)) += parts.col(a);
        }
      }
    }
  }
  if (parallel) {
#pragma omp parallel for schedule(static)
    for (int v = 0; v < num_vertices_; ++v) {
      Eigen::Vector3d sum = Eigen::Vector3d::Zero();
      for (int k = vertex_offsets_[static_cast<std::size_t>(v)];
           k < vertex_offsets_[static_cast<std::size_t>(v) + 1]; ++k) {
        const int incidence = vertex_incidences_[static_cast<std::size_t>(k)];
        sum += element_parts_[static_cast<std::size_t>(incidence / 4)].col(incidence % 4);
      }
      element_sums_.col(v) = sum;
    }
  }
}

void ProjectiveDynamicsModel::assemble_rhs(const Eigen::Matrix3Xd& x) {
  // b - A x = -(the incremental potential's gradient) at x: inertia and damping, less the
  // elements' parts.
  for (int v = 0; v < num_vertices_; ++v) {
    rhs_.row(v) =
        (inertia_.col(v) - (mass_coefficient_ * masses_(v)) * x.col(v) - element_sums_.col(v))
            .transpose();
  }
  // Eliminated vertices: the move to their targets, and their columns' terms moved to the
  // right-hand side. Their own rows' values are kept: the holds' forces are read from them.
  for (std::size_t k = 0; k < eliminated_list_.size(); ++k) {
    const int v = eliminated_list_[k];
    eliminated_gradients_.col(static_cast<Eigen::Index>(k)) = -rhs_.row(v).transpose();
    rhs_.row(v) = (eliminated_targets_.col(static_cast<Eigen::Index>(k)) - x.col(v)).transpose();
  }
  for (const int v : eliminated_list_) {
    const Eigen::Vector3d move = rhs_.row(v).transpose();
    for (Eigen::SparseMatrix<double>::InnerIterator it(laplacian_, v); it; ++it) {
      if (eliminated_[static_cast<std::size_t>(it.row())] == 0) {
        rhs_.row(it.row()) -= it.value() * move.transpose();
      }
    }
  }
}

StepStats ProjectiveDynamicsModel::step(double dt, const StepInput& input) {
  StepStats stats;
  constraints_.bind(input.constraints);
  std::fill(wanted_.begin(), wanted_.end(), 0);
  multiplier_holds_.clear();
  for (const int v : constraints_.vertices()) {
    const PositionConstraint* hold = constraints_.of(v);
    if (is_exact(hold) && !hold->slides() && hold->anchors) {
      wanted_[static_cast<std::size_t>(v)] = 1;
    } else {
      multiplier_holds_.push_back(hold);
    }
  }
  if (!update_factor(dt, &stats.factorizations)) {
    constraints_.unbind();
    stats.finite = false;
    return stats;
  }
  stats.linear_solves += held_rows_.prepare(multiplier_holds_, *factor_);
  eliminated_targets_.resize(3, static_cast<Eigen::Index>(eliminated_list_.size()));
  for (std::size_t k = 0; k < eliminated_list_.size(); ++k) {
    if (const PositionConstraint* hold = constraints_.of(eliminated_list_[k])) {
      eliminated_targets_.col(static_cast<Eigen::Index>(k)) = hold->target;
    }
  }

  // The inertial prediction y, and the first iterate x_n + dt v_n: y less the loads'
  // displacement dt^2 a. Starting from y, a body at rest under gravity would start each step
  // dt^2 g away from where it rests, and a fixed number of iterations would bring it back only
  // to within rho^k of that: its rest would be off its equilibrium by the iterations' error.
  // From x_n + dt v_n a body at rest starts at its equilibrium and stays there.
  const double alpha_term = params_.rayleigh_mass / dt;
  for (int v = 0; v < num_vertices_; ++v) {
    Eigen::Vector3d acceleration = input.gravity;
    if (input.external_forces != nullptr) {
      acceleration += input.external_forces->col(v) / masses_(v);
    }
    iterate_.col(v) = positions_.col(v) + dt * velocities_.col(v);
    const Eigen::Vector3d predicted = iterate_.col(v) + (dt * dt) * acceleration;
    inertia_.col(v) = masses_(v) * (predicted / (dt * dt) + alpha_term * positions_.col(v));
  }
  for (const int v : constraints_.vertices()) {
    if (const PositionConstraint* hold = constraints_.of(v)) {
      iterate_.col(v) = hold->place(iterate_.col(v));
    }
  }

  // Local/global iterations, Chebyshev-accelerated when asked.
  const double rho2 = params_.chebyshev_rho * params_.chebyshev_rho;
  double omega = 1.0;
  double residual = 0.0;
  int iteration = 0;
  for (; iteration < params_.iterations;) {
    project_elements(iterate_);
    assemble_rhs(iterate_);
    factor_->solve(rhs_.data(), 3, solution_.data());  // the move: A^-1 (b - A x)
    ++stats.linear_solves;
    held_rows_.correct(solution_, iterate_);
    next_ = iterate_ + solution_.transpose();
    if (params_.chebyshev_rho > 0.0 && iteration >= params_.chebyshev_delay) {
      omega =
          iteration == params_.chebyshev_delay ? 2.0 / (2.0 - rho2) : 4.0 / (4.0 - rho2 * omega);
      // x_{k+1} = omega (x^_{k+1} - x_{k-1}) + x_{k-1}: an affine combination, so every
      // (linear) hold still holds.
      next_ = omega * (next_ - previous_) + previous_;
    }
    for (std::size_t k = 0; k < eliminated_list_.size(); ++k) {
      next_.col(eliminated_list_[k]) = eliminated_targets_.col(static_cast<Eigen::Index>(k));
    }
    previous_.swap(iterate_);
    iterate_.swap(next_);
    residual = (iterate_ - previous_).colwise().norm().maxCoeff() / rest_size_;
    ++iteration;
    if (params_.tolerance > 0.0 && residual < params_.tolerance) {
      break;
    }
  }
  stats.iterations = iteration;
  stats.residual = residual;
  if (params_.tolerance > 0.0 && !(residual < params_.tolerance)) {
    stats.truncated_solves = 1;
  }

  // The holds' forces: the multipliers.
  constraint_forces_.setZero();
  held_rows_.add_forces(iterate_, constraint_forces_);
  // At an eliminated vertex: the row's residual (A x^ - b)_v at the last solve's x^ = x_k +
  // move (the last gradient there plus A times the move), the force the hold had to add; the
  // same solve the multipliers come from, so both kinds of hold report the same force.
  for (std::size_t k = 0; k < eliminated_list_.size(); ++k) {
    const int v = eliminated_list_[k];
    Eigen::Vector3d force = eliminated_gradients_.col(static_cast<Eigen::Index>(k))
                            + (mass_coefficient_ * masses_(v)) * solution_.row(v).transpose();
    for (Eigen::SparseMatrix<double>::InnerIterator it(laplacian_, v); it; ++it) {
      force += it.value() * solution_.row(it.row()).transpose();
    }
    constraint_forces_.col(v) = force;
  }

  double constraint_error = 0.0;
  for (const int v : constraints_.exact_vertices()) {
    if (const PositionConstraint* hold = constraints_.of(v)) {
      constraint_error = std::max(constraint_error, hold->gap(iterate_.col(v)).norm());
    }
  }
  stats.max_constraint_error = constraint_error;
  velocities_ = (iterate_ - positions_) / dt;
  positions_ = iterate_;
  constraints_.unbind();
  stats.finite = state_finite(positions_, velocities_);
  return stats;
}

}  // namespace softbench::projective_dynamics
