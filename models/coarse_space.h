// SPDX-License-Identifier: MIT
#pragma once

#include "models/block_pattern.h"

#include <Eigen/Core>
#include <Eigen/SparseCore>

#include <cstddef>
#include <memory>
#include <span>
#include <vector>

namespace softbench {

class CholmodFactor;

/// Vertices grouped into aggregates of about `target` vertices, each connected in the pattern's
/// graph: grown breadth-first from the lowest vertex not yet taken (the models number vertices
/// so that neighbours are close, so the aggregates come out compact), and an aggregate left
/// with fewer than a quarter of the target (a corner the others fenced in) joined to its
/// largest neighbour. aggregate_of[v] for each vertex, the ids 0, 1, ... in order of their
/// lowest vertex. `target` <= 0 or >= the vertex count: one aggregate.
std::vector<int> grow_aggregates(const BlockPattern& pattern, int target);

/// The coarse space of the SSOR solver's two-level solve (ssor_solver.h): the three
/// translations of each aggregate of vertices, W (3N x 3G, W_v = I in the columns of v's
/// aggregate). Loaded from the system matrix A every solve: A W and U W (U: A's blocks above the
/// diagonal) block by vertex, and E = W^T A W, a sparse 3G x 3G matrix, factorised by CHOLMOD
/// (its pattern analysed once, here).
///
/// The deflation keeps every iteration's residual orthogonal to W, so what the sweeps smooth
/// slowest, an aggregate's displacement as a whole, is solved exactly on the coarse level: the
/// iterations no longer grow with the mesh as the sweeps' did, and a free body's momentum is
/// kept (one aggregate: the whole body's three translations).
class CoarseSpace {
 public:
  CoarseSpace(const BlockPattern& pattern, std::vector<int> aggregate_of);
  ~CoarseSpace();
  CoarseSpace(const CoarseSpace&) = delete;
  CoarseSpace& operator=(const CoarseSpace&) = delete;

  /// E's unknowns from which its factor is supernodal (BLAS-3 on dense blocks; E fills in
  /// nearly dense as the aggregates grow in number) rather than simplicial (less overhead on a
  /// small E). Measured in instructions (callgrind) on the tests' elastic boxes: with 78
  /// unknowns the supernodal factor cost the solves 2% more, with 648 (about liver_x16's 684
  /// at aggregates of 64) it halved the factorisation and its solves were no dearer.
  static constexpr int kSupernodalFrom = 256;

  int num_aggregates() const { return num_aggregates_; }
  int aggregate(int vertex) const { return aggregate_of_[static_cast<std::size_t>(vertex)]; }

  /// A W, U W and E from the matrix's values (its vertex ranges side by side); false if E is not
  /// positive definite (a singular or non-finite system).
  bool load(const BlockPattern& a);
  /// load() in two parts, for a caller that overlaps E's factorisation with work of its own:
  /// load_blocks() (A W's and U W's blocks, the ranges side by side), then finish_load() (E
  /// from them, factorised, on the calling thread; false as load()).
  void load_blocks(const BlockPattern& a);
  bool finish_load();

  /// coarse() = W^T y, summed over `ranges` side by side (over_ranges()) and then in the ranges'
  /// order: the same at any thread count.
  void restrict_to_coarse(std::span<const int> ranges, const double* y);
  /// coarse() = (A W)^T y in the same order, in pieces for a loop that makes y range by range
  /// (the solver's backward sweep): clear_restriction(ranges); in each range's loop,
  /// add_product(v, y_v, slice) for its vertices with slice = restriction_slice(ranges, first,
  /// last); then finish_restriction(ranges).
  void clear_restriction(std::span<const int> ranges);
  double* restriction_slice(std::span<const int> ranges, int first, int last);
  /// slice += (A W)_v^T y_v.
  void add_product(int v, const double* yv, double* slice) const {
    const int begin = touch_offsets_[static_cast<std::size_t>(v)];
    const int end = touch_offsets_[static_cast<std::size_t>(v) + 1];
    const double* block = full_blocks_.data() + 9 * begin;
    for (int k = begin; k < end; ++k, block += 9) {
      double* o = slice + 3 * touch_aggregates_[static_cast<std::size_t>(k)];
      // (block^T y)_i = sum_k block(k, i) y_k: column i of the block.
      o[0] += block[0] * yv[0] + block[1] * yv[1] + block[2] * yv[2];
      o[1] += block[3] * yv[0] + block[4] * yv[1] + block[5] * yv[2];
      o[2] += block[6] * yv[0] + block[7] * yv[1] + block[8] * yv[2];
    }
  }
  void finish_restriction(std::span<const int> ranges);
  /// coarse() = E^-1 coarse().
  void solve();
  const Eigen::VectorXd& coarse() const { return coarse_vector_; }

  /// (W mu)_v for mu = coarse(): v's aggregate's translation.
  const double* translation(int v) const {
    return coarse_vector_.data() + 3 * static_cast<std::ptrdiff_t>(aggregate(v));
  }
  /// (A W mu)_v (`upper` false) or (U W mu)_v, the part from v's neighbours after it, for
  /// mu = coarse(), into out[3].
  void product_at(int v, bool upper, double* out) const {
    const int begin = touch_offsets_[static_cast<std::size_t>(v)];
    const int end = touch_offsets_[static_cast<std::size_t>(v) + 1];
    const double* blocks = (upper ? upper_blocks_ : full_blocks_).data() + 9 * begin;
    double o0 = 0.0;
    double o1 = 0.0;
    double o2 = 0.0;
    for (int k = 0; k < end - begin; ++k, blocks += 9) {
      const double* m =
          coarse_vector_.data() + 3 * touch_aggregates_[static_cast<std::size_t>(begin + k)];
      o0 += blocks[0] * m[0] + blocks[3] * m[1] + blocks[6] * m[2];
      o1 += blocks[1] * m[0] + blocks[4] * m[1] + blocks[7] * m[2];
      o2 += blocks[2] * m[0] + blocks[5] * m[1] + blocks[8] * m[2];
    }
    out[0] = o0;
    out[1] = o1;
    out[2] = o2;
  }

  /// E = W^T A W as last loaded (for tests).
  const Eigen::SparseMatrix<double>& coarse_matrix() const { return coarse_; }

  std::size_t memory_bytes() const;

 private:
  int num_aggregates_ = 0;
  std::vector<int> aggregate_of_;
  std::vector<int> touch_offsets_;     ///< #V + 1: vertex v's touches (aggregates it couples to)
  std::vector<int> touch_aggregates_;  ///< per touch, the aggregate; increasing for each vertex
  std::vector<int> slot_touch_;  ///< per neighbour slot of the pattern: its touch, from v's first
  std::vector<double> full_blocks_;   ///< 9 per touch, column-major: sum over n in g of A_vn
  std::vector<double> upper_blocks_;  ///< 9 per touch: the same over the neighbours n > v
  std::vector<int> coarse_entries_;   ///< 3 per touch: where its block's columns go in E
  Eigen::SparseMatrix<double> coarse_;
  std::unique_ptr<CholmodFactor> factor_;  ///< made once E's pattern is known
  Eigen::VectorXd coarse_vector_;
  Eigen::VectorXd solution_;
  std::vector<double> range_sums_;  ///< the restrictions' per-range parts (kMaxRanges slices)
};

}  // namespace softbench
