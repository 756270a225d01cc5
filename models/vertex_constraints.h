// SPDX-License-Identifier: MIT
#pragma once

#include "models/soft_body.h"

#include <cstddef>
#include <span>
#include <vector>

namespace softbench {

/// The constraint acting on each vertex during one step: the last one listed for a vertex wins,
/// and vertices out of range are ignored (step() never throws). bind() at the start of a step,
/// unbind() at its end; nothing allocates after construction.
class VertexConstraints {
 public:
  explicit VertexConstraints(int num_vertices);

  void bind(std::span<const PositionConstraint> constraints);
  void unbind();

  /// The constraint on `vertex` this step, or null.
  const PositionConstraint* of(int vertex) const {
    const int index = index_[static_cast<std::size_t>(vertex)];
    return index < 0 ? nullptr : &constraints_[static_cast<std::size_t>(index)];
  }
  /// Every constrained vertex once, in the order of the list's first mention.
  std::span<const int> vertices() const { return vertices_; }
  /// The exactly constrained vertices among them, in the same order.
  std::span<const int> exact_vertices() const { return exact_vertices_; }

  std::size_t memory_bytes() const;

 private:
  std::span<const PositionConstraint> constraints_;
  std::vector<int> index_;  ///< per vertex: into constraints_, or -1
  std::vector<int> vertices_;
  std::vector<int> exact_vertices_;
};

}  // namespace softbench
