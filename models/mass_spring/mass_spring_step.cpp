// SPDX-License-Identifier: MIT
// One step of the mass-spring model: spring forces and their Jacobians, symplectic Euler, and
// linearised backward Euler (Baraff & Witkin 1998) with exact constraints by elimination.
#include "models/double_lanes.h"
#include "models/finite_state.h"
#include "models/mass_spring/mass_spring_model.h"
#include "models/phase_clock.h"

#include <algorithm>
#include <cmath>
#include <cstddef>

namespace softbench::mass_spring {
namespace {

/// Loops over springs and vertices run on one thread below this many vertices, as the implicit
/// models' other loops (BlockPattern::kParallelVertices): on the liver (1215 vertices, 6802
/// springs) a pass costs ~0.05 ms, less than what a parallel region risks on a shared machine
/// when the other thread is descheduled (corotational_fem_step.cpp measured a time slice).
constexpr int kParallelVertices = BlockPattern::kParallelVertices;

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

SpringSystem::Preconditioner preconditioner_of(const MassSpringParams& params) {
  return params.preconditioner == MassSpringParams::Preconditioner::kSsor
             ? SpringSystem::Preconditioner::kSsor
             : SpringSystem::Preconditioner::kBlockJacobi;
}

}  // namespace

StepStats MassSpringModel::step_timed(double dt, const StepInput& input, PhaseTimes* times) {
  constraints_.bind(input.constraints);
  const StepStats stats = params_.integrator == MassSpringParams::Integrator::kSymplecticEuler
                              ? step_symplectic(dt, input)
                              : step_implicit(dt, input, times);
  constraints_.unbind();
  return stats;
}

void MassSpringModel::compute_spring_forces() {
  const Eigen::Index num_springs = springs_.cols();
#pragma omp parallel for schedule(static) if (num_vertices_ > kParallelVertices)
  for (Eigen::Index e = 0; e < num_springs; ++e) {
    const int i = springs_(0, e);
    const int j = springs_(1, e);
    spring_forces_.col(e) = spring_force(spring_stiffness_(e), rest_lengths_(e), spring_damping_(e),
                                         spring_geometry(positions_.col(i), positions_.col(j)),
                                         velocities_.col(j) - velocities_.col(i));
  }
}

void MassSpringModel::compute_spring_linearization(double dt) {
  const Eigen::Index num_springs = springs_.cols();
  const double* x = positions_.data();
  const double* v = velocities_.data();
  const int* ends = springs_.data();
  const double* rest_lengths = rest_lengths_.data();
  const double* stiffness = spring_stiffness_.data();
  const double* damping = spring_damping_.data();
  double* rhs = spring_rhs_.data();
  const SpringSystem::SpringColumns columns = system_.spring_columns();
  // Two springs at a time (their square roots and divisions in one instruction each): a third of
  // the instructions one at a time took. With an odd count the last pair is the last spring
  // twice, written twice with the same values.
  const Eigen::Index num_pairs = (num_springs + 1) / 2;
#pragma omp parallel for schedule(static) if (num_vertices_ > kParallelVertices)
  for (Eigen::Index pair = 0; pair < num_pairs; ++pair) {
    const Eigen::Index e = 2 * pair;
    const Eigen::Index f = std::min(e + 1, num_springs - 1);
    const double* xi[2] = {x + 3 * ends[2 * e], x + 3 * ends[2 * f]};
    const double* xj[2] = {x + 3 * ends[2 * e + 1], x + 3 * ends[2 * f + 1]};
    const double* vi[2] = {v + 3 * ends[2 * e], v + 3 * ends[2 * f]};
    const double* vj[2] = {v + 3 * ends[2 * e + 1], v + 3 * ends[2 * f + 1]};
    Pair delta[3];
    Pair relative[3];
    for (int a = 0; a < 3; ++a) {
      delta[a] = Pair{xj[0][a], xj[1][a]} - Pair{xi[0][a], xi[1][a]};
      relative[a] = Pair{vj[0][a], vj[1][a]} - Pair{vi[0][a], vi[1][a]};
    }
    const Pair length = sqrt_pair(delta[0] * delta[0] + delta[1] * delta[1] + delta[2] * delta[2]);
    const Pair zero = {0.0, 0.0};
    // A collapsed spring has no direction: no force is better than a NaN.
    const Pair inverse_length = length > 0.0 ? 1.0 / length : zero;
    const Pair d[3] = {delta[0] * inverse_length, delta[1] * inverse_length,
                       delta[2] * inverse_length};
    const Pair rate = d[0] * relative[0] + d[1] * relative[1] + d[2] * relative[2];
    const Pair rest_length = {rest_lengths[e], rest_lengths[f]};
    const Pair k = {stiffness[e], stiffness[f]};
    const Pair c = {damping[e], damping[f]};
    // K_e = -k S with S = d d^T + t (I - d d^T), t = max(0, 1 - L/l): the transverse
    // (geometric) term is dropped under compression, where it would make K indefinite (Baraff &
    // Witkin 1998).
    const Pair stretched = 1.0 - rest_length * inverse_length;
    const Pair transverse = length > 0.0 && stretched > 0.0 ? stretched : zero;
    // On vertex i: the force f_e = (k (l - L) + c rate) d, plus dt K_e (v_i - v_j) =
    // dt k S (v_j - v_i) = dt k ((1 - t) rate d + t (v_j - v_i)).
    const Pair along_force =
        k * (length - rest_length) + c * rate + dt * k * (1.0 - transverse) * rate;
    const Pair across_rate = dt * k * transverse;
    for (int a = 0; a < 3; ++a) {
      const Pair value = along_force * d[a] + across_rate * relative[a];
      rhs[3 * e + a] = value[0];
      rhs[3 * f + a] = value[1];
    }
    // The spring's share of A = M - dt D - dt^2 K, with D_e = -c d d^T (the dashpot):
    // dt c d d^T + dt^2 k S = (dt c + dt^2 k (1 - t)) d d^T + dt^2 k t I, both coefficients
    // non-negative (1 - t = min(1, L/l) > 0).
    const Pair along = sqrt_pair(dt * c + dt * dt * k * (1.0 - transverse));
    const Pair u[3] = {along * d[0], along * d[1], along * d[2]};
    const Pair across = dt * across_rate;
    for (const Eigen::Index spring : {e, f}) {
      const int lane = spring == e ? 0 : 1;
      columns.ux[spring] = u[0][lane];
      columns.uy[spring] = u[1][lane];
      columns.uz[spring] = u[2][lane];
      columns.across[spring] = across[lane];
    }
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
  const std::vector<int>& incident = system_.incident_springs();
#pragma omp parallel for schedule(static) if (num_vertices_ > kParallelVertices)
  for (int v = 0; v < num_vertices_; ++v) {
    const PositionConstraint* constraint = constraints_.of(v);
    Eigen::Vector3d force = vertex_force(v, input, constraint);
    for (int k = system_.incident_begin(v); k < system_.incident_end(v); ++k) {
      const int e = incident[static_cast<std::size_t>(k)];
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
  const std::vector<int>& incident = system_.incident_springs();
#pragma omp parallel for schedule(static) if (num_vertices_ > kParallelVertices)
  for (int v = 0; v < num_vertices_; ++v) {
    const PositionConstraint* constraint = constraints_.of(v);
    Eigen::Vector3d force = vertex_force(v, input, constraint);
    Eigen::Matrix3d penalty = Eigen::Matrix3d::Zero();
    if (is_penalty(constraint)) {
      // A penalty spring to the target: K = -k_p H (H the held directions), so A gains
      // dt^2 k_p H and b gains dt K v.
      const Eigen::Matrix3d held = constraint->stiffness * constraint->held;
      penalty = (dt * dt) * held;
      force -= dt * held * velocities_.col(v);
    }
    for (int k = system_.incident_begin(v); k < system_.incident_end(v); ++k) {
      const int e = incident[static_cast<std::size_t>(k)];
      force += springs_(0, e) == v ? spring_rhs_.col(e) : Eigen::Vector3d(-spring_rhs_.col(e));
    }
    rhs_.segment<3>(3 * v) = dt * force;
    // M - dt D for the mass damping D = -c_m m I, and the springs' blocks.
    system_.set_vertex(v, masses_(v) * (1.0 + dt * params_.mass_damping), penalty);
  }
}

SolveReport MassSpringModel::solve_cholmod() {
#pragma omp parallel for schedule(static) if (num_vertices_ > kParallelVertices)
  for (int v = 0; v < num_vertices_; ++v) {
    pattern_->set(pattern_->vertex_block(v), system_.vertex_block(v));
  }
  const Eigen::Index num_springs = springs_.cols();
#pragma omp parallel for schedule(static) if (num_vertices_ > kParallelVertices)
  for (Eigen::Index e = 0; e < num_springs; ++e) {
    // The spring blocks are symmetric, so both off-diagonal positions get the same values.
    const Eigen::Matrix3d coupling = -system_.spring_block(e);
    pattern_->set(pattern_->edge_block(static_cast<int>(e)), coupling);
    pattern_->set(pattern_->edge_block_transposed(static_cast<int>(e)), coupling);
  }
  cholmod_rhs_ = rhs_;
  elimination_.eliminate(*pattern_, constraints_, known_changes_, cholmod_rhs_, velocity_change_);
  const SolveReport report = solver_->solve(*pattern_, cholmod_rhs_, velocity_change_, nullptr);
  elimination_.to_world(velocity_change_);
  return report;
}

void MassSpringModel::compute_implicit_reactions(double dt) {
  constraint_forces_.setZero();
  for (const int v : constraints_.vertices()) {
    const PositionConstraint* constraint = constraints_.of(v);
    if (is_penalty(constraint)) {
      constraint_forces_.col(v) = constraint->stiffness * constraint->gap(positions_.col(v));
    } else if (is_exact(constraint)) {
      // A sliding vertex's free rows were solved, not held: what is left of them is the
      // solver's residual, not a force of the constraint.
      const Eigen::Vector3d residual = system_.row(v, velocity_change_) - rhs_.segment<3>(3 * v);
      constraint_forces_.col(v) = constraint->held * residual / dt;
    }
  }
}

StepStats MassSpringModel::step_implicit(double dt, const StepInput& input, PhaseTimes* times) {
  PhaseClock clock(times);
  system_.bind(constraints_);
  compute_spring_linearization(dt);
  clock.lap(&PhaseTimes::springs);
  assemble_implicit_system(dt, input);
  system_.prepare();
  exact_velocity_changes(constraints_, positions_, velocities_, dt, known_changes_);

  clock.lap(&PhaseTimes::assembly);

  SolveReport report;
  if (pattern_ != nullptr) {
    report = solve_cholmod();  // its matrix assembly is timed with the solve
  } else {
    system_.set_energy_floor(resting_energy(total_mass_, rest_size_, dt));
    report =
        system_.solve(rhs_, known_changes_, velocity_change_, velocities_,
                      preconditioner_of(params_), params_.cg_tolerance, params_.cg_max_iterations);
  }
  clock.lap(&PhaseTimes::solve);

  apply_velocity_change(constraints_, dt, velocity_change_, positions_, velocities_);
  compute_implicit_reactions(dt);

  StepStats stats = finish_step();
  stats.iterations = report.iterations;
  stats.residual = report.residual;
  stats.factorizations = report.factorizations;
  stats.linear_solves = 1;
  stats.truncated_solves = report.converged ? 0 : 1;
  stats.finite = stats.finite && report.succeeded;
  clock.lap(&PhaseTimes::update);
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
  stats.finite = state_finite(positions_, velocities_);
  return stats;
}

}  // namespace softbench::mass_spring
