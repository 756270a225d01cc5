// SPDX-License-Identifier: MIT
#include "models/implicit_system.h"

#include <Eigen/Eigenvalues>

#include <algorithm>
#include <cmath>

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

  rotate_sliding(pattern, constraints, rhs, solution);

  for (const int c : exact) {
    if (constraints.of(c)->slides()) {
      continue;
    }
    const Eigen::Vector3d value = known.col(c);
    const std::span<const int> neighbours = pattern.neighbours(c);
    for (std::size_t slot = 0; slot < neighbours.size(); ++slot) {
      const int other = neighbours[slot];
      const BlockEntries column = pattern.column_block(c, static_cast<int>(slot));
      if (other != c && !holds_fully(constraints.of(other))) {
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
  for (std::size_t k = 0; k < sliding_.size(); ++k) {
    const int c = sliding_[k];
    const int known_count = held_counts_[k];
    // The known coordinates: the first known_count of the vertex's frame.
    const Eigen::Vector3d value = frames_[k].transpose() * known.col(c);
    const std::span<const int> neighbours = pattern.neighbours(c);
    for (std::size_t slot = 0; slot < neighbours.size(); ++slot) {
      const int other = neighbours[slot];
      if (holds_fully(constraints.of(other))) {
        continue;  // its blocks with c are zero already
      }
      const BlockEntries column = pattern.column_block(c, static_cast<int>(slot));
      Eigen::Matrix3d block = pattern.get(column);
      if (other == c) {
        for (int a = 0; a < known_count; ++a) {
          for (int b = known_count; b < 3; ++b) {
            rhs(3 * c + b) -= block(b, a) * value(a);
          }
        }
        block.topRows(known_count).setZero();
        block.leftCols(known_count).setZero();
        for (int a = 0; a < known_count; ++a) {
          block(a, a) = 1.0;
        }
        pattern.set(column, block);
        continue;
      }
      rhs.segment<3>(3 * other) -= block.leftCols(known_count) * value.head(known_count);
      block.leftCols(known_count).setZero();
      pattern.set(column, block);
      const BlockEntries row = pattern.row_block(c, static_cast<int>(slot));
      Eigen::Matrix3d mirrored = pattern.get(row);
      mirrored.topRows(known_count).setZero();
      pattern.set(row, mirrored);
    }
  }
  for (const int c : exact) {
    if (!constraints.of(c)->slides()) {
      rhs.segment<3>(3 * c) = known.col(c);
      solution.segment<3>(3 * c) = known.col(c);
    }
  }
  for (std::size_t k = 0; k < sliding_.size(); ++k) {
    const int c = sliding_[k];
    const Eigen::Vector3d value = frames_[k].transpose() * known.col(c);
    for (int a = 0; a < held_counts_[k]; ++a) {
      rhs(3 * c + a) = value(a);
      solution(3 * c + a) = value(a);
    }
  }
}

bool ConstraintElimination::holds_fully(const PositionConstraint* constraint) {
  return is_exact(constraint) && !constraint->slides();
}

void ConstraintElimination::rotate_sliding(BlockPattern& pattern,
                                           const VertexConstraints& constraints,
                                           Eigen::VectorXd& rhs,
                                           Eigen::VectorXd& solution) {
  sliding_.clear();
  held_counts_.clear();
  frames_.clear();
  for (const int c : constraints.exact_vertices()) {
    const PositionConstraint* constraint = constraints.of(c);
    if (constraint == nullptr || !constraint->slides()) {
      continue;
    }
    // The held directions first (the projector's eigenvalue-1 eigenvectors), then the free.
    const Eigen::SelfAdjointEigenSolver<Eigen::Matrix3d> eigen(constraint->held);
    const int known_count = static_cast<int>(std::lround(constraint->held.trace()));
    Eigen::Matrix3d frame;
    for (int a = 0; a < 3; ++a) {
      frame.col(a) = eigen.eigenvectors().col(2 - a);  // eigenvalues ascend
    }
    sliding_.push_back(c);
    held_counts_.push_back(known_count);
    frames_.push_back(frame);
  }
  // A <- T^T A T in two passes: the columns of every sliding vertex times its Q, then its rows
  // times Q^T (its diagonal block, stored once, gets both: Q^T A_cc Q).
  for (std::size_t k = 0; k < sliding_.size(); ++k) {
    const int c = sliding_[k];
    const auto degree = static_cast<int>(pattern.neighbours(c).size());
    for (int slot = 0; slot < degree; ++slot) {
      const BlockEntries column = pattern.column_block(c, slot);
      pattern.set(column, Eigen::Matrix3d(pattern.get(column) * frames_[k]));
    }
  }
  for (std::size_t k = 0; k < sliding_.size(); ++k) {
    const int c = sliding_[k];
    const auto degree = static_cast<int>(pattern.neighbours(c).size());
    for (int slot = 0; slot < degree; ++slot) {
      const BlockEntries row = pattern.row_block(c, slot);
      pattern.set(row, Eigen::Matrix3d(frames_[k].transpose() * pattern.get(row)));
    }
    rhs.segment<3>(3 * c) = frames_[k].transpose() * rhs.segment<3>(3 * c);
    solution.segment<3>(3 * c) = frames_[k].transpose() * solution.segment<3>(3 * c);
  }
}

void ConstraintElimination::to_world(Eigen::VectorXd& solution) const {
  for (std::size_t k = 0; k < sliding_.size(); ++k) {
    const int c = sliding_[k];
    solution.segment<3>(3 * c) = frames_[k] * solution.segment<3>(3 * c);
  }
}

const double* ConstraintElimination::in_frame(const Eigen::Matrix3Xd& values) {
  if (sliding_.empty()) {
    return values.data();
  }
  framed_ = Eigen::Map<const Eigen::VectorXd>(values.data(), values.size());
  for (std::size_t k = 0; k < sliding_.size(); ++k) {
    const int c = sliding_[k];
    framed_.segment<3>(3 * c) = frames_[k].transpose() * framed_.segment<3>(3 * c);
  }
  return framed_.data();
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
  return (vertices_.capacity() + value_offsets_.capacity() + sliding_.capacity()
          + held_counts_.capacity())
             * sizeof(int)
         + (saved_values_.capacity() + saved_rhs_.capacity()) * sizeof(double)
         + frames_.capacity() * sizeof(Eigen::Matrix3d)
         + static_cast<std::size_t>(framed_.size()) * sizeof(double);
}

void exact_velocity_changes(const VertexConstraints& constraints,
                            const Eigen::Matrix3Xd& positions,
                            const Eigen::Matrix3Xd& velocities,
                            double dt,
                            Eigen::Matrix3Xd& changes) {
  for (const int v : constraints.exact_vertices()) {
    // What lands the free flight x + dt v on the target (along the normal: on its plane).
    changes.col(v) =
        constraints.of(v)->gap(positions.col(v) + dt * velocities.col(v)) / dt;
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
      const Eigen::Vector3d new_position = constraint->place(
          positions.col(v) + dt * (velocities.col(v) + velocity_change.segment<3>(3 * v)));
      const Eigen::Vector3d new_velocity = (new_position - positions.col(v)) / dt;
      velocity_change.segment<3>(3 * v) = new_velocity - velocities.col(v);
      velocities.col(v) = new_velocity;
      positions.col(v) = new_position;
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
      forces.col(v) = constraint->stiffness * constraint->gap(positions.col(v));
    }
  }
  elimination.constrained_residuals(pattern, velocity_change, forces);
  for (const int v : constraints.exact_vertices()) {
    // A sliding vertex's tangential rows were solved, not held: what is left of them is the
    // solver's residual, not a force of the constraint.
    forces.col(v) = constraints.of(v)->held * forces.col(v) / dt;
  }
}

}  // namespace softbench
