// SPDX-License-Identifier: MIT
#include "models/implicit_system.h"

#include <algorithm>

namespace softbench {

void ConstraintElimination::eliminate(BlockPattern& pattern,
                                      const VertexConstraints& constraints,
                                      const Eigen::Matrix3Xd& known,
                                      Eigen::VectorXd& rhs,
                                      Eigen::VectorXd& solution) {
  const std::span<const int> exact = constraints.exact_vertices();
  double* values = pattern.matrix().valuePtr();

  // Save the rows first: eliminating one vertex zeroes blocks in its neighbours' columns.
  vertices_.assign(exact.begin(), exact.end());
  value_offsets_.resize(exact.size() + 1);
  value_offsets_[0] = 0;
  for (std::size_t k = 0; k < exact.size(); ++k) {
    value_offsets_[k + 1] =
        value_offsets_[k] + 9 * static_cast<int>(pattern.neighbours(exact[k]).size());
  }
  saved_values_.resize(static_cast<std::size_t>(value_offsets_.back()));
  saved_rhs_.resize(3 * exact.size());
  for (std::size_t k = 0; k < exact.size(); ++k) {
    const int c = exact[k];
    const double* begin = values + pattern.column_values_begin(c);
    std::copy(begin, begin + (value_offsets_[k + 1] - value_offsets_[k]),
              saved_values_.begin() + value_offsets_[k]);
    for (int a = 0; a < 3; ++a) {
      saved_rhs_[3 * k + static_cast<std::size_t>(a)] = rhs(3 * c + a);
    }
  }

  for (const int c : exact) {
    const Eigen::Vector3d value = known.col(c);
    const std::span<const int> neighbours = pattern.neighbours(c);
    for (std::size_t slot = 0; slot < neighbours.size(); ++slot) {
      const int other = neighbours[slot];
      const BlockEntries column = pattern.column_block(c, static_cast<int>(slot));
      if (other != c && !is_exact(constraints.of(other))) {
        // b_o -= A_oc u_c, A_oc being block (o, c) in c's columns.
        rhs.segment<3>(3 * other) -= pattern.get(column) * value;
      }
      if (other == c) {
        pattern.set(column, Eigen::Matrix3d::Identity());
      } else {
        pattern.set(column, Eigen::Matrix3d::Zero());
        pattern.set(pattern.row_block(c, static_cast<int>(slot)), Eigen::Matrix3d::Zero());
      }
    }
  }
  for (const int c : exact) {
    rhs.segment<3>(3 * c) = known.col(c);
    solution.segment<3>(3 * c) = known.col(c);
  }
}

void ConstraintElimination::constrained_residuals(const BlockPattern& pattern,
                                                  const Eigen::VectorXd& solution,
                                                  Eigen::Matrix3Xd& residuals) const {
  for (std::size_t k = 0; k < vertices_.size(); ++k) {
    const int c = vertices_[k];
    const std::span<const int> neighbours = pattern.neighbours(c);
    const auto degree = static_cast<int>(neighbours.size());
    const double* columns = saved_values_.data() + value_offsets_[k];
    Eigen::Vector3d row = Eigen::Vector3d::Zero();
    for (int b = 0; b < 3; ++b) {
      // Row c, entry b of A u: column 3c + b of the symmetric A, dotted with u.
      const double* column = columns + 3 * degree * b;
      for (int slot = 0; slot < degree; ++slot) {
        row(b) +=
            column[3 * slot] * solution(3 * neighbours[static_cast<std::size_t>(slot)])
            + column[3 * slot + 1] * solution(3 * neighbours[static_cast<std::size_t>(slot)] + 1)
            + column[3 * slot + 2] * solution(3 * neighbours[static_cast<std::size_t>(slot)] + 2);
      }
      row(b) -= saved_rhs_[3 * k + static_cast<std::size_t>(b)];
    }
    residuals.col(c) = row;
  }
}

std::size_t ConstraintElimination::memory_bytes() const {
  return (vertices_.capacity() + value_offsets_.capacity()) * sizeof(int)
         + (saved_values_.capacity() + saved_rhs_.capacity()) * sizeof(double);
}

void exact_velocity_changes(const VertexConstraints& constraints,
                            const Eigen::Matrix3Xd& positions,
                            const Eigen::Matrix3Xd& velocities,
                            double dt,
                            Eigen::Matrix3Xd& changes) {
  for (const int v : constraints.exact_vertices()) {
    changes.col(v) = (constraints.of(v)->target - positions.col(v)) / dt - velocities.col(v);
  }
}

void apply_velocity_change(const VertexConstraints& constraints,
                           double dt,
                           Eigen::VectorXd& velocity_change,
                           Eigen::Matrix3Xd& positions,
                           Eigen::Matrix3Xd& velocities) {
  const auto num_vertices = static_cast<int>(positions.cols());
#pragma omp parallel for schedule(static) if (num_vertices > BlockPattern::kParallelVertices)
  for (int v = 0; v < num_vertices; ++v) {
    const PositionConstraint* constraint = constraints.of(v);
    if (is_exact(constraint)) {
      const Eigen::Vector3d new_velocity = (constraint->target - positions.col(v)) / dt;
      velocity_change.segment<3>(3 * v) = new_velocity - velocities.col(v);
      velocities.col(v) = new_velocity;
      positions.col(v) = constraint->target;
    } else {
      velocities.col(v) += velocity_change.segment<3>(3 * v);
      positions.col(v) += dt * velocities.col(v);
    }
  }
}

void implicit_reactions(const ConstraintElimination& elimination,
                        const BlockPattern& pattern,
                        const VertexConstraints& constraints,
                        const Eigen::Matrix3Xd& positions,
                        const Eigen::VectorXd& velocity_change,
                        double dt,
                        Eigen::Matrix3Xd& forces) {
  forces.setZero();
  for (const int v : constraints.vertices()) {
    const PositionConstraint* constraint = constraints.of(v);
    if (is_penalty(constraint)) {
      forces.col(v) = constraint->stiffness * (constraint->target - positions.col(v));
    }
  }
  elimination.constrained_residuals(pattern, velocity_change, forces);
  for (const int v : constraints.exact_vertices()) {
    forces.col(v) /= dt;
  }
}

}  // namespace softbench
