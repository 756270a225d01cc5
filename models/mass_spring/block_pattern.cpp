// SPDX-License-Identifier: MIT
#include "models/mass_spring/block_pattern.h"

#include <algorithm>

namespace softbench::mass_spring {
namespace {

/// Every vertex's block columns: itself and its edge neighbours, sorted.
std::vector<std::vector<int>> block_columns(int num_vertices, const Eigen::Matrix2Xi& edges) {
  std::vector<std::vector<int>> neighbours(static_cast<std::size_t>(num_vertices));
  for (int v = 0; v < num_vertices; ++v) {
    neighbours[static_cast<std::size_t>(v)].push_back(v);
  }
  for (Eigen::Index e = 0; e < edges.cols(); ++e) {
    neighbours[static_cast<std::size_t>(edges(0, e))].push_back(edges(1, e));
    neighbours[static_cast<std::size_t>(edges(1, e))].push_back(edges(0, e));
  }
  for (auto& list : neighbours) {
    std::sort(list.begin(), list.end());
  }
  return neighbours;
}

}  // namespace

BlockPattern::BlockPattern(int num_vertices, const Eigen::Matrix2Xi& edges) {
  const std::vector<std::vector<int>> neighbours = block_columns(num_vertices, edges);
  const Eigen::Index size = 3 * static_cast<Eigen::Index>(num_vertices);
  matrix_.resize(size, size);
  Eigen::VectorXi entries_per_column(size);
  for (int v = 0; v < num_vertices; ++v) {
    const int count = 3 * static_cast<int>(neighbours[static_cast<std::size_t>(v)].size());
    entries_per_column.segment<3>(3 * v).setConstant(count);
  }
  matrix_.reserve(entries_per_column);
  // Column by column with rows increasing: insertion never moves an entry.
  for (int column_vertex = 0; column_vertex < num_vertices; ++column_vertex) {
    for (int b = 0; b < 3; ++b) {
      for (const int row_vertex : neighbours[static_cast<std::size_t>(column_vertex)]) {
        for (int a = 0; a < 3; ++a) {
          matrix_.insert(3 * row_vertex + a, 3 * column_vertex + b) = 0.0;
        }
      }
    }
  }
  matrix_.makeCompressed();

  // Entry (row, column) by binary search in its column: done once here, never per step.
  const auto entry_index = [this](int row, int column) {
    const int* begin = matrix_.innerIndexPtr() + matrix_.outerIndexPtr()[column];
    const int* end = matrix_.innerIndexPtr() + matrix_.outerIndexPtr()[column + 1];
    return static_cast<int>(std::lower_bound(begin, end, row) - matrix_.innerIndexPtr());
  };
  const auto block_entries = [&entry_index](int row_vertex, int column_vertex) {
    BlockEntries where{};
    for (int a = 0; a < 3; ++a) {
      for (int b = 0; b < 3; ++b) {
        where[static_cast<std::size_t>(3 * a + b)] =
            entry_index(3 * row_vertex + a, 3 * column_vertex + b);
      }
    }
    return where;
  };
  vertex_blocks_.reserve(static_cast<std::size_t>(num_vertices));
  for (int v = 0; v < num_vertices; ++v) {
    vertex_blocks_.push_back(block_entries(v, v));
  }
  edge_blocks_.reserve(static_cast<std::size_t>(edges.cols()));
  for (Eigen::Index e = 0; e < edges.cols(); ++e) {
    edge_blocks_.push_back(
        {block_entries(edges(0, e), edges(1, e)), block_entries(edges(1, e), edges(0, e))});
  }
}

std::size_t BlockPattern::memory_bytes() const {
  const auto nonzeros = static_cast<std::size_t>(matrix_.nonZeros());
  return nonzeros * (sizeof(double) + sizeof(int))
         + static_cast<std::size_t>(matrix_.outerSize() + 1) * sizeof(int)
         + vertex_blocks_.size() * sizeof(BlockEntries)
         + edge_blocks_.size() * 2 * sizeof(BlockEntries);
}

}  // namespace softbench::mass_spring
