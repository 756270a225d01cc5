// SPDX-License-Identifier: MIT
#pragma once

#include "models/double_lanes.h"

#include <Eigen/Core>
#include <Eigen/SparseCore>

#include <array>
#include <cstddef>
#include <span>
#include <vector>

namespace softbench {

/// Where a 3x3 block sits in a BlockPattern matrix's value array: entry (a, b) (row a, column b
/// of the block) at offset + a + stride b, the block being three strips of three values, one in
/// each of its columns (the layout below). where[3 a + b] is that position. Two ints, not nine
/// positions: assembling the liver wrote about as many bytes of positions as of values.
struct BlockEntries {
  int offset = 0;  ///< the position of entry (0, 0)
  int stride = 0;  ///< from one column's strip to the next: the values in a column
  int operator[](std::size_t k) const {
    return offset + static_cast<int>(k / 3) + stride * static_cast<int>(k % 3);
  }
};

/// The fixed sparsity pattern of a symmetric 3N x 3N system with one 3x3 block per vertex (the
/// diagonal) and two per edge (i, j): (i, j) and (j, i). Both triangles are stored so the same
/// matrix serves a full sparse product (CG, residuals) and CHOLMOD (which reads the lower
/// triangle only). Used by every implicit model (mass-spring, corotational FEM).
///
/// Built once: every step only overwrites values through the precomputed entry indices, so no
/// step allocates, searches or changes the pattern (CHOLMOD's symbolic analysis stays valid).
///
/// Layout (what multiply() relies on): the matrix is column-major; the three columns of vertex c
/// hold, for each neighbour n of c in increasing order (c itself included), the three rows of n
/// consecutively. So block (n, c) is three strips of three values, one strip per column.
class BlockPattern {
 public:
  /// `edges`: 2 x #E vertex pairs, each pair at most once, no self-loops.
  BlockPattern(int num_vertices, const Eigen::Matrix2Xi& edges);

  int num_vertices() const { return num_vertices_; }
  Eigen::Index size() const { return 3 * static_cast<Eigen::Index>(num_vertices_); }

  /// Vertex ranges no block joins (PartitionedOrder::offsets: `parts` ranges, then a separator
  /// that may couple to any vertex), for Gauss-Seidel sweeps over the parts side by side. Throws
  /// std::invalid_argument if the offsets do not cover the vertices in order or a block joins
  /// two parts. The default: one part, an empty separator.
  void set_parts(std::vector<int> offsets);
  /// parts() + 2 offsets: part k is [offsets[k], offsets[k + 1]), the separator the last range.
  std::span<const int> part_offsets() const { return part_offsets_; }
  int parts() const { return static_cast<int>(part_offsets_.size()) - 2; }
  /// Whether the products and sweeps run on the OpenMP threads: above kParallelVertices, or when
  /// the model numbered its vertices into parts for its threads (its step then chooses, step by
  /// step, whether to use them: ThreadChoice).
  bool threaded() const { return num_vertices_ > kParallelVertices || parts() > 1; }

  /// The matrix with the pattern; all values zero until written.
  Eigen::SparseMatrix<double>& matrix() { return matrix_; }
  const Eigen::SparseMatrix<double>& matrix() const { return matrix_; }

  const BlockEntries& vertex_block(int vertex) const { return vertex_blocks_[vertex]; }
  /// The block coupling the edge's first vertex (rows) to its second (columns).
  const BlockEntries& edge_block(int edge) const { return edge_blocks_[edge][0]; }
  /// The transposed position: second vertex (rows), first vertex (columns).
  const BlockEntries& edge_block_transposed(int edge) const { return edge_blocks_[edge][1]; }

  /// The vertices whose blocks share rows with `vertex` (its edge neighbours and itself),
  /// increasing.
  std::span<const int> neighbours(int vertex) const {
    return {neighbours_.data() + neighbour_offsets_[vertex],
            neighbours_.data() + neighbour_offsets_[vertex + 1]};
  }
  /// The entries of block (row vertex neighbours(vertex)[slot], column vertex `vertex`).
  BlockEntries column_block(int vertex, int slot) const;
  /// The entries of the mirrored block (row `vertex`, column vertex neighbours(vertex)[slot]).
  BlockEntries row_block(int vertex, int slot) const;
  /// The first of vertex's 9 * neighbours(vertex).size() values: its three columns, contiguous.
  int column_values_begin(int vertex) const { return matrix_.outerIndexPtr()[3 * vertex]; }
  /// The vertex's own slot in neighbours(vertex): its diagonal block's strips.
  int own_slot(int vertex) const {
    return (vertex_blocks_[static_cast<std::size_t>(vertex)][0] - column_values_begin(vertex)) / 3;
  }

  /// sum over the neighbours n of vertex c before it (lower) or after it (upper) of A_cn y_n,
  /// into out[3] (y: 3 values per vertex). The two halves of a Gauss-Seidel sweep's row (the
  /// SSOR solver's) and of quadratic_form().
  [[gnu::always_inline]] void neighbour_sum(int c, bool lower, const double* y, double* out) const {
    neighbour_sum(c, lower, matrix_.valuePtr(), y, out);
  }
  /// The same from `values`, an array laid out as the matrix's values: they themselves, or a
  /// copy in single precision (the SSOR solver's, LinearSolverOptions::single_precision_sweeps).
  template <class Value>
  [[gnu::always_inline]] void neighbour_sum(
      int c, bool lower, const Value* values, const double* y, double* out) const {
    // Row c of the symmetric matrix is column c: block (c, n) is the transpose of the strip of n
    // in c's columns, so (A_cn y_n)_k = column k's strip of n dotted with y_n.
    const std::span<const int> row = neighbours(c);
    const auto degree = static_cast<int>(row.size());
    const int own = own_slot(c);
    const int first = lower ? 0 : own + 1;
    const int last = lower ? own : degree;
    const Value* column0 = values + column_values_begin(c);
    const Value* column1 = column0 + 3 * degree;
    const Value* column2 = column1 + 3 * degree;
    // Nine independent sums (a row of the block times a component of y_n each), as three
    // vectors: lane k of sum i adds column i's strip entry k times y_n's component k, so each
    // strip is one load of four lanes (the fourth is the next value in the array, times 0: a
    // strip is never the array's last, since the last vertex's last slot is its own) and a
    // neighbour three multiply-adds where scalars took nine. Each lane is the sum the scalar
    // loop made, in the same order: the results are the same to the bit.
    const int* neighbour = row.data();
    Quad sum0{};
    Quad sum1{};
    Quad sum2{};
    // The sweep's newest value is its nearest neighbour's (c - 1 forward, c + 1 backward: the
    // vertex order keeps neighbours close), so that neighbour is added last, and the sums over the
    // others do not wait for it: ascending for the lower part, descending for the upper.
    const int step = lower ? 1 : -1;
    const int begin = lower ? first : last - 1;
    for (int i = 0, slot = begin; i < last - first; ++i, slot += step) {
      const double* yn = y + 3 * neighbour[slot];
      const Quad components = {yn[0], yn[1], yn[2], 0.0};  // y + 3 n + 3 may be past the end
      const int at = 3 * slot;
      sum0 += load_quad(column0 + at) * components;
      sum1 += load_quad(column1 + at) * components;
      sum2 += load_quad(column2 + at) * components;
    }
    out[0] = (sum0[0] + sum0[1]) + sum0[2];
    out[1] = (sum1[0] + sum1[1]) + sum1[2];
    out[2] = (sum2[0] + sum2[1]) + sum2[2];
  }

  /// Writes `block` (a 3x3 matrix) into the entries `where`.
  template <class Block>
  void set(const BlockEntries& where, const Block& block) {
    double* values = matrix_.valuePtr() + where.offset;
    for (int b = 0; b < 3; ++b) {
      for (int a = 0; a < 3; ++a) {
        values[a + where.stride * b] = block(a, b);
      }
    }
  }
  Eigen::Matrix3d get(const BlockEntries& where) const;

  /// y = A x (both of size()), from the columns of the symmetric matrix: row i of A is column i,
  /// so each output entry is a gather over one contiguous column (three per vertex, sharing the
  /// neighbour indices). Deterministic: each entry is summed in a fixed order whatever the thread
  /// count. If `chunk_dots` is not empty (num_chunks() entries), entry k receives the part of
  /// x . y over chunk k: summed in order by the caller, the dot product is independent of the
  /// thread count too. Parallel (OpenMP, static) when threaded().
  void multiply(const Eigen::VectorXd& x,
                Eigen::VectorXd& y,
                std::span<double> chunk_dots = {}) const;

  /// x^T A x (x of size()), from the diagonal blocks and the blocks above them only: A is
  /// symmetric, so half the matrix is read (a product and a dot read all of it). `chunk_sums`
  /// (num_chunks() entries) is scratch for the per-chunk parts, summed in order: deterministic
  /// and parallel as multiply().
  double quadratic_form(const Eigen::VectorXd& x, std::span<double> chunk_sums) const;

  /// y[k] = A x[k] for every k (at most kManyVectors): multiply() for several vectors in one
  /// pass over the matrix, each value read once and applied to all of them (the liver's matrix,
  /// 1.3 MB, does not fit in L2). Deterministic and parallel as multiply() (its sums in another
  /// fixed order: the two agree to round-off).
  static constexpr int kManyVectors = 4;
  void multiply_many(std::span<const Eigen::VectorXd* const> x,
                     std::span<Eigen::VectorXd* const> y) const;

  /// Deterministic reductions split the 3N entries into chunks of this many vertices
  /// (multiply() and the CG vector loops).
  static constexpr int kChunkVertices = 256;
  /// Below this many vertices a product runs on one thread (unless threaded() says otherwise): a
  /// parallel region costs a few microseconds, as much as the product of a ~1000-vertex matrix
  /// saves on two cores, and when another process holds a core every region waits for it.
  static constexpr int kParallelVertices = 2048;
  int num_chunks() const { return (num_vertices_ + kChunkVertices - 1) / kChunkVertices; }

  std::size_t memory_bytes() const;

 private:
  int num_vertices_ = 0;
  Eigen::SparseMatrix<double> matrix_;
  std::vector<int> neighbour_offsets_;  ///< #V + 1
  std::vector<int> neighbours_;         ///< per vertex, sorted, itself included
  std::vector<int> mirror_slots_;       ///< per neighbours_ entry (c, n): c's slot in n's list
  std::vector<BlockEntries> vertex_blocks_;
  std::vector<std::array<BlockEntries, 2>> edge_blocks_;
  std::vector<int> part_offsets_;
};

}  // namespace softbench
