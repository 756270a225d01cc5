// SPDX-License-Identifier: MIT
#pragma once

#include <Eigen/Core>
#include <Eigen/SparseCore>

#include <array>
#include <cstddef>
#include <vector>

namespace softbench::mass_spring {

/// Where each entry of a 3x3 block sits in a sparse matrix's value array; entry (a, b) (row a,
/// column b of the block) is at position 3 a + b.
using BlockEntries = std::array<int, 9>;

/// The fixed sparsity pattern of a 3N x 3N system with one 3x3 block per vertex (the diagonal)
/// and two per edge (i, j): (i, j) and (j, i). Both triangles are stored so the same matrix serves
/// a full sparse product (CG, residuals) and CHOLMOD (which reads the lower triangle only).
///
/// Built once: every step only overwrites values through the precomputed entry indices, so no
/// step allocates, searches or changes the pattern (CHOLMOD's symbolic analysis stays valid).
class BlockPattern {
 public:
  /// `edges`: 2 x #E vertex pairs, each pair at most once, no self-loops.
  BlockPattern(int num_vertices, const Eigen::Matrix2Xi& edges);

  /// The matrix with the pattern; all values zero until written.
  Eigen::SparseMatrix<double>& matrix() { return matrix_; }
  const Eigen::SparseMatrix<double>& matrix() const { return matrix_; }

  const BlockEntries& vertex_block(int vertex) const { return vertex_blocks_[vertex]; }
  /// The block coupling the edge's first vertex (rows) to its second (columns).
  const BlockEntries& edge_block(int edge) const { return edge_blocks_[edge][0]; }
  /// The transposed position: second vertex (rows), first vertex (columns).
  const BlockEntries& edge_block_transposed(int edge) const { return edge_blocks_[edge][1]; }

  /// Writes `block` (a 3x3 matrix) into the entries `where`.
  template <class Block>
  void set(const BlockEntries& where, const Block& block) {
    double* values = matrix_.valuePtr();
    for (int a = 0; a < 3; ++a) {
      for (int b = 0; b < 3; ++b) {
        values[where[3 * a + b]] = block(a, b);
      }
    }
  }

  std::size_t memory_bytes() const;

 private:
  Eigen::SparseMatrix<double> matrix_;
  std::vector<BlockEntries> vertex_blocks_;
  std::vector<std::array<BlockEntries, 2>> edge_blocks_;
};

}  // namespace softbench::mass_spring
