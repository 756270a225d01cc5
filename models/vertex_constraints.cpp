// SPDX-License-Identifier: MIT
#include "models/vertex_constraints.h"

namespace softbench {

VertexConstraints::VertexConstraints(int num_vertices)
    : index_(static_cast<std::size_t>(num_vertices), -1) {
  vertices_.reserve(static_cast<std::size_t>(num_vertices));
  exact_vertices_.reserve(static_cast<std::size_t>(num_vertices));
}

void VertexConstraints::bind(std::span<const PositionConstraint> constraints) {
  constraints_ = constraints;
  const auto num_vertices = static_cast<int>(index_.size());
  for (std::size_t k = 0; k < constraints.size(); ++k) {
    const int vertex = constraints[k].vertex;
    if (vertex < 0 || vertex >= num_vertices) {
      continue;
    }
    int& index = index_[static_cast<std::size_t>(vertex)];
    if (index < 0) {
      vertices_.push_back(vertex);  // within the reserved capacity: no allocation
    }
    index = static_cast<int>(k);
  }
  for (const int vertex : vertices_) {
    if (is_exact(of(vertex))) {
      exact_vertices_.push_back(vertex);
    }
  }
}

void VertexConstraints::unbind() {
  for (const int vertex : vertices_) {
    index_[static_cast<std::size_t>(vertex)] = -1;
  }
  vertices_.clear();
  exact_vertices_.clear();
  constraints_ = {};
}

std::size_t VertexConstraints::memory_bytes() const {
  return (index_.capacity() + vertices_.capacity() + exact_vertices_.capacity()) * sizeof(int);
}

}  // namespace softbench
