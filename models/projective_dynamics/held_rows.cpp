// SPDX-License-Identifier: MIT
#include "models/projective_dynamics/held_rows.h"

#include "models/memory_bytes.h"

#include <Eigen/Eigenvalues>

#include <algorithm>

namespace softbench::projective_dynamics {

HeldRows::HeldRows(int num_vertices)
    : num_vertices_(num_vertices), slot_(static_cast<std::size_t>(num_vertices), -1) {}

void HeldRows::forget() {
  std::fill(slot_.begin(), slot_.end(), -1);
  slot_vertex_.clear();
  slot_step_.clear();  // the storage stays: the next factor's columns go there
}

int HeldRows::prepare(std::span<const PositionConstraint* const> holds, CholmodFactor& factor) {
  ++step_;
  rows_.clear();
  missing_.clear();
  for (const PositionConstraint* hold : holds) {
    const int vertex = hold->vertex;
    const double compliance = is_exact(hold) ? 0.0 : 1.0 / hold->stiffness;
    if (!hold->slides()) {
      for (int axis = 0; axis < 3; ++axis) {
        const Eigen::Vector3d direction = Eigen::Vector3d::Unit(axis);
        rows_.push_back({vertex, -1, direction, hold->target(axis), compliance});
      }
    } else {
      // The held directions: the projector's eigenvectors of eigenvalue 1 (the rest are 0).
      const Eigen::SelfAdjointEigenSolver<Eigen::Matrix3d> eigen(hold->held);
      for (int k = 0; k < 3; ++k) {
        if (eigen.eigenvalues()(k) > 0.5) {
          const Eigen::Vector3d direction = eigen.eigenvectors().col(k);
          rows_.push_back({vertex, -1, direction, direction.dot(hold->target), compliance});
        }
      }
    }
    // One hold per vertex (VertexConstraints): a vertex is missing at most once.
    if (const int slot = column_of(vertex); slot >= 0) {
      slot_step_[static_cast<std::size_t>(slot)] = step_;
    } else {
      missing_.push_back(vertex);
    }
  }

  // Over the bound, keep only the columns this step uses (moved to the front, in order).
  const std::size_t bound = std::max<std::size_t>(kMinKeptColumns, 2 * holds.size());
  if (slot_vertex_.size() + missing_.size() > bound) {
    std::size_t kept = 0;
    for (std::size_t from = 0; from < slot_vertex_.size(); ++from) {
      const auto vertex = static_cast<std::size_t>(slot_vertex_[from]);
      if (slot_step_[from] != step_) {
        slot_[vertex] = -1;
        continue;
      }
      if (kept != from) {
        columns_.col(static_cast<Eigen::Index>(kept)) =
            columns_.col(static_cast<Eigen::Index>(from));
        slot_vertex_[kept] = slot_vertex_[from];
        slot_step_[kept] = step_;
      }
      slot_[vertex] = static_cast<int>(kept++);
    }
    slot_vertex_.resize(kept);
    slot_step_.resize(kept);
  }

  // The missing columns, in one multi-column solve, into storage that grows by doubling (up
  // to the bound): a step that brings new vertices into contact rarely copies the kept ones.
  const auto missing = static_cast<Eigen::Index>(missing_.size());
  if (missing > 0) {
    const auto first = static_cast<Eigen::Index>(slot_vertex_.size());
    if (columns_.cols() < first + missing) {
      // first + missing <= bound after the eviction above.
      const auto capacity = std::min(static_cast<Eigen::Index>(bound),
                                     std::max(first + missing, 2 * columns_.cols()));
      columns_.conservativeResize(num_vertices_, capacity);
    }
    unit_rhs_.setZero(num_vertices_, missing);
    for (Eigen::Index k = 0; k < missing; ++k) {
      const int vertex = missing_[static_cast<std::size_t>(k)];
      unit_rhs_(vertex, k) = 1.0;
      slot_[static_cast<std::size_t>(vertex)] = static_cast<int>(first + k);
      slot_vertex_.push_back(vertex);
      slot_step_.push_back(step_);
    }
    factor.solve(unit_rhs_.data(), static_cast<int>(missing), columns_.col(first).data());
  }

  const auto size = static_cast<Eigen::Index>(rows_.size());
  for (Row& row : rows_) {
    row.column = column_of(row.vertex);
  }
  system_.resize(size, size);
  for (Eigen::Index r = 0; r < size; ++r) {
    const Row& column_row = rows_[static_cast<std::size_t>(r)];
    for (Eigen::Index q = r; q < size; ++q) {
      const Row& row = rows_[static_cast<std::size_t>(q)];
      const double value =
          columns_(row.vertex, column_row.column) * row.direction.dot(column_row.direction);
      system_(q, r) = value;
      system_(r, q) = value;
    }
    system_(r, r) += column_row.compliance;
  }
  if (size > 0) {
    llt_.compute(system_);
  }
  multipliers_.setZero(size);
  return static_cast<int>(missing);
}

void HeldRows::correct(Eigen::MatrixX3d& move, const Eigen::Matrix3Xd& base) {
  if (rows_.empty()) {
    return;
  }
  gaps_.resize(static_cast<Eigen::Index>(rows_.size()));
  for (std::size_t r = 0; r < rows_.size(); ++r) {
    const Row& row = rows_[r];
    gaps_(static_cast<Eigen::Index>(r)) =
        row.target - row.direction.dot(base.col(row.vertex) + move.row(row.vertex).transpose());
  }
  multipliers_ = llt_.solve(gaps_);
  // One rank-one update per held vertex (its rows are consecutive).
  for (std::size_t r = 0; r < rows_.size();) {
    const Row& first = rows_[r];
    Eigen::Vector3d force = Eigen::Vector3d::Zero();
    for (; r < rows_.size() && rows_[r].vertex == first.vertex; ++r) {
      force += multipliers_(static_cast<Eigen::Index>(r)) * rows_[r].direction;
    }
    move.noalias() += columns_.col(first.column) * force.transpose();
  }
}

void HeldRows::add_forces(const Eigen::Matrix3Xd& positions, Eigen::Matrix3Xd& forces) const {
  for (std::size_t r = 0; r < rows_.size(); ++r) {
    const Row& row = rows_[r];
    const double force =
        row.compliance > 0.0
            ? (row.target - row.direction.dot(positions.col(row.vertex))) / row.compliance
            : multipliers_(static_cast<Eigen::Index>(r));
    forces.col(row.vertex) += force * row.direction;
  }
}

std::size_t HeldRows::memory_bytes() const {
  return bytes_of_elements(rows_) + bytes_of_elements(slot_) + bytes_of_elements(slot_vertex_)
         + bytes_of_elements(slot_step_) + bytes_of(columns_) + bytes_of(system_)
         + bytes_of(multipliers_) + bytes_of(gaps_) + bytes_of_elements(missing_)
         + bytes_of(unit_rhs_);
}

}  // namespace softbench::projective_dynamics
