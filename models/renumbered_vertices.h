// SPDX-License-Identifier: MIT
#pragma once

#include "geometry/tet_mesh.h"
#include "geometry/vertex_order.h"
#include "models/soft_body.h"

#include <Eigen/Core>
#include <Eigen/SparseCore>

#include <cstddef>
#include <vector>

namespace softbench {

/// A mesh renumbered for a model's own use, the order that did it, and the ranges of the new
/// numbering its sweeps may run side by side (PartitionedOrder::offsets).
struct RenumberedMesh {
  VertexOrder order;
  TetMesh mesh;
  std::vector<int> part_offsets;
};

/// `mesh` renumbered by reverse Cuthill-McKee and then, for `parts` > 1, cut into that many parts
/// and a separator (geometry/vertex_order.h).
RenumberedMesh renumbered_for_locality(const TetMesh& mesh, int parts = 1);

/// A model that numbers the vertices its own way behind the SoftBody interface, whose vertices are
/// the TetMesh's: what comes in (constraints, forces, states) is mapped to the model's numbering,
/// what goes out back to the mesh's, and the published state (positions(), velocities()) is
/// kept here in the mesh's. The mapping copies a few vectors a step; the model's passes over
/// neighbours then read nearby memory.
class RenumberedVertices {
 public:
  explicit RenumberedVertices(VertexOrder order) : order_(std::move(order)) {}

  /// The model's state, in the mesh's numbering: what SoftBody::positions() and velocities()
  /// return. Sized once (no allocation after the first call).
  void publish(const Eigen::Matrix3Xd& positions, const Eigen::Matrix3Xd& velocities);
  const Eigen::Matrix3Xd& positions() const { return positions_; }
  const Eigen::Matrix3Xd& velocities() const { return velocities_; }

  /// inner.col(new_of_old[v]) = outer.col(v).
  void to_inner(const Eigen::Matrix3Xd& outer, Eigen::Matrix3Xd& inner) const;
  /// outer.col(old_of_new[i]) = inner.col(i).
  void to_outer(const Eigen::Matrix3Xd& inner, Eigen::Matrix3Xd& outer) const;
  Eigen::Matrix3Xd to_outer(const Eigen::Matrix3Xd& inner) const;
  /// The model's vertex `inner` in the mesh's numbering.
  int to_outer(int inner) const { return order_.old_of_new[static_cast<std::size_t>(inner)]; }
  /// A 3#V x 3#V matrix in the model's numbering, in the mesh's.
  Eigen::SparseMatrix<double> to_outer(const Eigen::SparseMatrix<double>& inner) const;
  /// `input` in the model's numbering: its constraints and forces are copied into storage kept
  /// here (valid until the next call; allocates only when the constraint count grows).
  StepInput to_inner(const StepInput& input);

  std::size_t memory_bytes() const;

 private:
  VertexOrder order_;
  Eigen::Matrix3Xd positions_;   ///< published, in the mesh's numbering
  Eigen::Matrix3Xd velocities_;  ///< published, in the mesh's numbering
  std::vector<PositionConstraint> constraints_;
  Eigen::Matrix3Xd forces_;
};

}  // namespace softbench
