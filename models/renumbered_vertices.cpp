// SPDX-License-Identifier: MIT
#include "models/renumbered_vertices.h"

#include "models/memory_bytes.h"

#include <vector>

namespace softbench {

RenumberedMesh renumbered_for_locality(const TetMesh& mesh, int parts) {
  VertexOrder order = reverse_cuthill_mckee(mesh.tets(), mesh.num_vertices());
  TetMesh inner = renumbered(mesh, order);
  PartitionedOrder cut = partitioned(inner.tets(), inner.num_vertices(), parts);
  if (cut.offsets.size() > 3) {
    // Compose: old vertex v is RCM's new_of_old[v], which the cut numbers anew.
    for (int& index : order.new_of_old) {
      index = cut.order.new_of_old[static_cast<std::size_t>(index)];
    }
    for (std::size_t v = 0; v < order.new_of_old.size(); ++v) {
      order.old_of_new[static_cast<std::size_t>(order.new_of_old[v])] = static_cast<int>(v);
    }
    inner = renumbered(mesh, order);
  }
  return RenumberedMesh{std::move(order), std::move(inner), std::move(cut.offsets)};
}

void RenumberedVertices::to_inner(const Eigen::Matrix3Xd& outer, Eigen::Matrix3Xd& inner) const {
  inner.resize(3, outer.cols());
  for (Eigen::Index v = 0; v < outer.cols(); ++v) {
    inner.col(order_.new_of_old[static_cast<std::size_t>(v)]) = outer.col(v);
  }
}

void RenumberedVertices::to_outer(const Eigen::Matrix3Xd& inner, Eigen::Matrix3Xd& outer) const {
  outer.resize(3, inner.cols());
  for (Eigen::Index i = 0; i < inner.cols(); ++i) {
    outer.col(order_.old_of_new[static_cast<std::size_t>(i)]) = inner.col(i);
  }
}

void RenumberedVertices::publish(const Eigen::Matrix3Xd& positions,
                                 const Eigen::Matrix3Xd& velocities) {
  to_outer(positions, positions_);
  to_outer(velocities, velocities_);
}

Eigen::Matrix3Xd RenumberedVertices::to_outer(const Eigen::Matrix3Xd& inner) const {
  Eigen::Matrix3Xd outer;
  to_outer(inner, outer);
  return outer;
}

Eigen::SparseMatrix<double> RenumberedVertices::to_outer(
    const Eigen::SparseMatrix<double>& inner) const {
  const auto outer_index = [this](Eigen::Index i) {
    return 3 * static_cast<Eigen::Index>(order_.old_of_new[static_cast<std::size_t>(i / 3)])
           + i % 3;
  };
  std::vector<Eigen::Triplet<double>> entries;
  entries.reserve(static_cast<std::size_t>(inner.nonZeros()));
  for (Eigen::Index column = 0; column < inner.outerSize(); ++column) {
    for (Eigen::SparseMatrix<double>::InnerIterator it(inner, column); it; ++it) {
      entries.emplace_back(outer_index(it.row()), outer_index(it.col()), it.value());
    }
  }
  Eigen::SparseMatrix<double> outer(inner.rows(), inner.cols());
  outer.setFromTriplets(entries.begin(), entries.end());
  return outer;
}

StepInput RenumberedVertices::to_inner(const StepInput& input) {
  StepInput inner;
  inner.gravity = input.gravity;
  constraints_.assign(input.constraints.begin(), input.constraints.end());
  const auto num_vertices = static_cast<int>(order_.new_of_old.size());
  for (PositionConstraint& constraint : constraints_) {
    if (constraint.vertex >= 0 && constraint.vertex < num_vertices) {
      constraint.vertex = order_.new_of_old[static_cast<std::size_t>(constraint.vertex)];
    }  // else left out of range, for the model's own check to reject
  }
  inner.constraints = constraints_;
  if (input.external_forces != nullptr) {
    to_inner(*input.external_forces, forces_);
    inner.external_forces = &forces_;
  }
  return inner;
}

std::size_t RenumberedVertices::memory_bytes() const {
  return bytes_of_elements(order_.new_of_old) + bytes_of_elements(order_.old_of_new)
         + bytes_of(positions_) + bytes_of(velocities_) + bytes_of_elements(constraints_)
         + bytes_of(forces_);
}

}  // namespace softbench
