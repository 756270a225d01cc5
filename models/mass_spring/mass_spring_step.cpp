// SPDX-License-Identifier: MIT
// One step of the mass-spring model: spring forces and their Jacobians, symplectic Euler, and
// linearised backward Euler (Baraff & Witkin 1998) with exact constraints by elimination.
#include "models/mass_spring/mass_spring_model.h"

#include <algorithm>
#include <cstddef>

namespace softbench::mass_spring {
namespace {

/// Loops shorter than this run on one thread: starting a parallel region costs more than it saves.
constexpr Eigen::Index kParallelThreshold = 4096;

using ConstBlock = Eigen::Map<const Eigen::Matrix3d>;
using Block = Eigen::Map<Eigen::Matrix3d>;

/// A spring's current length and unit direction from its first vertex to its second.
struct SpringGeometry {
  double length = 0.0;
  Eigen::Vector3d direction = Eigen::Vector3d::Zero();  ///< zero for a collapsed spring
};

SpringGeometry spring_geometry(const Eigen::Vector3d& first, const Eigen::Vector3d& second) {
  const Eigen::Vector3d delta = second - first;
  SpringGeometry geometry;
  geometry.length = delta.norm();
  // A collapsed spring has no direction: no force is better than a NaN.
  if (geometry.length > 0.0) {
    geometry.direction = delta / geometry.length;
  }
  return geometry;
}

/// Elastic k (l - L) d plus dashpot c ((v_j - v_i) . d) d, on the first vertex.
Eigen::Vector3d spring_force(double stiffness,
                             double rest_length,
                             double damping,
                             const SpringGeometry& geometry,
                             const Eigen::Vector3d& relative_velocity) {
  const double stretch_rate = relative_velocity.dot(geometry.direction);
  return (stiffness * (geometry.length - rest_length) + damping * stretch_rate)
         * geometry.direction;
}

}  // namespace

StepStats MassSpringModel::step(double dt, const StepInput& input) {
  constraints_.bind(input.constraints);
  const StepStats stats = params_.integrator == MassSpringParams::Integrator::kSymplecticEuler
                              ? step_symplectic(dt, input)
                              : step_implicit(dt, input);
  constraints_.unbind();
  return stats;
}

void MassSpringModel::compute_spring_forces() {
  const Eigen::Index num_springs = springs_.cols();
#pragma omp parallel for schedule(static) if (num_springs > kParallelThreshold)
  for (Eigen::Index e = 0; e < num_springs; ++e) {
    const int i = springs_(0, e);
    const int j = springs_(1, e);
    spring_forces_.col(e) = spring_force(spring_stiffness_(e), rest_lengths_(e), params_.damping,
                                         spring_geometry(positions_.col(i), positions_.col(j)),
                                         velocities_.col(j) - velocities_.col(i));
  }
}

void MassSpringModel::compute_spring_linearization(double dt) {
  const Eigen::Index num_springs = springs_.cols();
#pragma omp parallel for schedule(static) if (num_springs > kParallelThreshold)
  for (Eigen::Index e = 0; e < num_springs; ++e) {
    const int i = springs_(0, e);
    const int j = springs_(1, e);
    const SpringGeometry geometry = spring_geometry(positions_.col(i), positions_.col(j));
    const Eigen::Vector3d& d = geometry.direction;
    const double length = geometry.length;
    const Eigen::Vector3d relative_velocity = velocities_.col(j) - velocities_.col(i);
    const double k = spring_stiffness_(e);
    const Eigen::Vector3d force =
        spring_force(k, rest_lengths_(e), params_.damping, geometry, relative_velocity);
    // K_e = -k S with S = d d^T + max(0, 1 - L/l) (I - d d^T): the transverse (geometric) term
    // is dropped under compression, where it would make K indefinite (Baraff & Witkin 1998).
    const Eigen::Matrix3d along = d * d.transpose();
    const double transverse = length > 0.0 ? std::max(0.0, 1.0 - rest_lengths_(e) / length) : 0.0;
    const Eigen::Matrix3d s = along + transverse * (Eigen::Matrix3d::Identity() - along);
    // On vertex i: f_e + dt K_e (v_i - v_j) = f_e + dt k S (v_j - v_i).
    spring_rhs_.col(e) = force + dt * k * (s * relative_velocity);
    // The spring's share of A = M - dt D - dt^2 K, with D_e = -c d d^T (the dashpot).
    Block(spring_blocks_.col(e).data()) = dt * params_.damping * along + dt * dt * k * s;
  }
}

Eigen::Vector3d MassSpringModel::vertex_force(int vertex,
                                              const StepInput& input,
                                              const PositionConstraint* constraint) const {
  const double mass = masses_(vertex);
  Eigen::Vector3d force =
      mass * input.gravity - params_.mass_damping * mass * velocities_.col(vertex);
  if (input.external_forces != nullptr) {
    force += input.external_forces->col(vertex);
  }
  if (is_penalty(constraint)) {
    force += constraint->stiffness * constraint->gap(positions_.col(vertex));
  }
  return force;
}

StepStats MassSpringModel::step_symplectic(double dt, const StepInput& input) {
  compute_spring_forces();
#pragma omp parallel for schedule(static) if (num_vertices_ > kParallelThreshold)
  for (int v = 0; v < num_vertices_; ++v) {
    const PositionConstraint* constraint = constraints_.of(v);
    Eigen::Vector3d force = vertex_force(v, input, constraint);
    for (int k = incident_offsets_[static_cast<std::size_t>(v)];
         k < incident_offsets_[static_cast<std::size_t>(v) + 1]; ++k) {
      const int e = incident_springs_[static_cast<std::size_t>(k)];
      force +=
          springs_(0, e) == v ? spring_forces_.col(e) : Eigen::Vector3d(-spring_forces_.col(e));
    }
    const double mass = masses_(v);
    if (is_exact(constraint)) {
      // The vertex lands on its target (a sliding one where its free step meets the plane); the
      // reaction is what its momentum change needed beyond the other forces.
      const Eigen::Vector3d free_position =
          positions_.col(v) + dt * (velocities_.col(v) + (dt / mass) * force);
      const Eigen::Vector3d placed = constraint->place(free_position);
      const Eigen::Vector3d new_velocity = (placed - positions_.col(v)) / dt;
      constraint_forces_.col(v) = mass * (new_velocity - velocities_.col(v)) / dt - force;
      velocities_.col(v) = new_velocity;
      positions_.col(v) = placed;  // exactly: x + dt v would round
      continue;
    }
    constraint_forces_.col(v) =
        is_penalty(constraint)
            ? Eigen::Vector3d(constraint->stiffness * constraint->gap(positions_.col(v)))
            : Eigen::Vector3d::Zero();
    velocities_.col(v) += (dt / mass) * force;
    positions_.col(v) += dt * velocities_.col(v);
  }
  return finish_step();
}

void MassSpringModel::assemble_implicit_system(double dt, const StepInput& input) {
#pragma omp parallel for schedule(static) if (num_vertices_ > kParallelThreshold)
  for (int v = 0; v < num_vertices_; ++v) {
    const PositionConstraint* constraint = constraints_.of(v);
    const double mass = masses_(v);
    // M - dt D for the mass damping D = -c_m m I.
    Eigen::Matrix3d block =
        (mass * (1.0 + dt * params_.mass_damping)) * Eigen::Matrix3d::Identity();
    Eigen::Vector3d force = vertex_force(v, input, constraint);
    if (is_penalty(constraint)) {
      // A penalty spring to the target: K = -k_p H (H the held directions), so A gains
      // dt^2 k_p H and b gains dt K v.
      const Eigen::Matrix3d held = constraint->stiffness * constraint->held;
      block += (dt * dt) * held;
      force -= dt * held * velocities_.col(v);
    }
    for (int k = incident_offsets_[static_cast<std::size_t>(v)];
         k < incident_offsets_[static_cast<std::size_t>(v) + 1]; ++k) {
      const int e = incident_springs_[static_cast<std::size_t>(k)];
      force += springs_(0, e) == v ? spring_rhs_.col(e) : Eigen::Vector3d(-spring_rhs_.col(e));
      block += ConstBlock(spring_blocks_.col(e).data());
    }
    pattern_->set(pattern_->vertex_block(v), block);
    rhs_.segment<3>(3 * v) = dt * force;
  }
  const Eigen::Index num_springs = springs_.cols();
#pragma omp parallel for schedule(static) if (num_springs > kParallelThreshold)
  for (Eigen::Index e = 0; e < num_springs; ++e) {
    // The spring blocks are symmetric, so both off-diagonal positions get the same values.
    const Eigen::Matrix3d coupling = -ConstBlock(spring_blocks_.col(e).data());
    pattern_->set(pattern_->edge_block(static_cast<int>(e)), coupling);
    pattern_->set(pattern_->edge_block_transposed(static_cast<int>(e)), coupling);
  }
}

void MassSpringModel::eliminate_exact_constraints(double dt) {
  exact_velocity_changes(constraints_, positions_, velocities_, dt, known_changes_);
  elimination_.eliminate(*pattern_, constraints_, known_changes_, rhs_, velocity_change_);
}

void MassSpringModel::compute_implicit_reactions(double dt) {
  implicit_reactions(elimination_, *pattern_, constraints_, positions_, velocity_change_, dt,
                     constraint_forces_);
}

StepStats MassSpringModel::step_implicit(double dt, const StepInput& input) {
  compute_spring_linearization(dt);
  assemble_implicit_system(dt, input);
  eliminate_exact_constraints(dt);
  const SolveReport report =
      solver_->solve(*pattern_, rhs_, velocity_change_, elimination_.in_frame(velocities_));
  elimination_.to_world(velocity_change_);

  apply_velocity_change(constraints_, dt, velocity_change_, positions_, velocities_);
  compute_implicit_reactions(dt);

  StepStats stats = finish_step();
  stats.iterations = report.iterations;
  stats.residual = report.residual;
  stats.factorizations = report.factorizations;
  stats.linear_solves = 1;
  stats.finite = stats.finite && report.succeeded;
  return stats;
}

StepStats MassSpringModel::finish_step() const {
  StepStats stats;
  for (const int v : constraints_.vertices()) {
    const PositionConstraint* constraint = constraints_.of(v);
    if (is_penalty(constraint)) {
      stats.max_constraint_error =
          std::max(stats.max_constraint_error, constraint->gap(positions_.col(v)).norm());
    }
  }
  stats.finite = positions_.allFinite() && velocities_.allFinite();
  return stats;
}

}  // namespace softbench::mass_spring
