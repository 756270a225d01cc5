// SPDX-License-Identifier: MIT
#include "models/block_pattern.h"

#include "models/double_lanes.h"
#include "models/memory_bytes.h"

#include <algorithm>
#include <cstring>
#include <stdexcept>
#include <string>

namespace softbench {

BlockPattern::BlockPattern(int num_vertices, const Eigen::Matrix2Xi& edges)
    : num_vertices_(num_vertices), part_offsets_{0, num_vertices, num_vertices} {
  // Every vertex's block columns: itself and its edge neighbours, sorted.
  std::vector<std::vector<int>> lists(static_cast<std::size_t>(num_vertices));
  for (int v = 0; v < num_vertices; ++v) {
    lists[static_cast<std::size_t>(v)].push_back(v);
  }
  for (Eigen::Index e = 0; e < edges.cols(); ++e) {
    lists[static_cast<std::size_t>(edges(0, e))].push_back(edges(1, e));
    lists[static_cast<std::size_t>(edges(1, e))].push_back(edges(0, e));
  }
  neighbour_offsets_.assign(static_cast<std::size_t>(num_vertices) + 1, 0);
  for (int v = 0; v < num_vertices; ++v) {
    auto& list = lists[static_cast<std::size_t>(v)];
    std::sort(list.begin(), list.end());
    neighbour_offsets_[static_cast<std::size_t>(v) + 1] =
        neighbour_offsets_[static_cast<std::size_t>(v)] + static_cast<int>(list.size());
  }
  neighbours_.reserve(static_cast<std::size_t>(neighbour_offsets_.back()));
  for (const auto& list : lists) {
    neighbours_.insert(neighbours_.end(), list.begin(), list.end());
  }
  mirror_slots_.resize(neighbours_.size());
  for (int v = 0; v < num_vertices; ++v) {
    for (int k = neighbour_offsets_[static_cast<std::size_t>(v)];
         k < neighbour_offsets_[static_cast<std::size_t>(v) + 1]; ++k) {
      const auto& other = lists[static_cast<std::size_t>(neighbours_[static_cast<std::size_t>(k)])];
      mirror_slots_[static_cast<std::size_t>(k)] =
          static_cast<int>(std::lower_bound(other.begin(), other.end(), v) - other.begin());
    }
  }

  const Eigen::Index size = 3 * static_cast<Eigen::Index>(num_vertices);
  matrix_.resize(size, size);
  Eigen::VectorXi entries_per_column(size);
  for (int v = 0; v < num_vertices; ++v) {
    const int count = 3 * static_cast<int>(lists[static_cast<std::size_t>(v)].size());
    entries_per_column.segment<3>(3 * v).setConstant(count);
  }
  matrix_.reserve(entries_per_column);
  // Column by column with rows increasing: insertion never moves an entry.
  for (int column_vertex = 0; column_vertex < num_vertices; ++column_vertex) {
    for (int b = 0; b < 3; ++b) {
      for (const int row_vertex : lists[static_cast<std::size_t>(column_vertex)]) {
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
  const auto block_entries = [this, &entry_index](int row_vertex, int column_vertex) {
    return BlockEntries{entry_index(3 * row_vertex, 3 * column_vertex),
                        matrix_.outerIndexPtr()[3 * column_vertex + 1]
                            - matrix_.outerIndexPtr()[3 * column_vertex]};
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

void BlockPattern::set_parts(std::vector<int> offsets) {
  const auto fail = [](const std::string& why) {
    throw std::invalid_argument("BlockPattern::set_parts: " + why);
  };
  if (offsets.size() < 3 || offsets.front() != 0 || offsets.back() != num_vertices_
      || !std::is_sorted(offsets.begin(), offsets.end())) {
    fail("the offsets must rise from 0 to the vertex count, a part at least and the separator");
  }
  const auto parts = static_cast<int>(offsets.size()) - 2;
  const int separator = offsets[static_cast<std::size_t>(parts)];
  for (int part = 0; part < parts; ++part) {
    const int first = offsets[static_cast<std::size_t>(part)];
    const int last = offsets[static_cast<std::size_t>(part) + 1];
    for (int v = first; v < last; ++v) {
      for (const int n : neighbours(v)) {
        if ((n < first || n >= last) && n < separator) {
          fail("vertices " + std::to_string(v) + " and " + std::to_string(n)
               + " are coupled across two parts");
        }
      }
    }
  }
  part_offsets_ = std::move(offsets);
}

BlockEntries BlockPattern::column_block(int vertex, int slot) const {
  const int degree = neighbour_offsets_[static_cast<std::size_t>(vertex) + 1]
                     - neighbour_offsets_[static_cast<std::size_t>(vertex)];
  return BlockEntries{matrix_.outerIndexPtr()[3 * vertex] + 3 * slot, 3 * degree};
}

BlockEntries BlockPattern::row_block(int vertex, int slot) const {
  // Block (vertex, n) lives in n's columns, at vertex's slot in n's list.
  const int k = neighbour_offsets_[static_cast<std::size_t>(vertex)] + slot;
  return column_block(neighbours_[static_cast<std::size_t>(k)],
                      mirror_slots_[static_cast<std::size_t>(k)]);
}

Eigen::Matrix3d BlockPattern::get(const BlockEntries& where) const {
  const double* values = matrix_.valuePtr();
  Eigen::Matrix3d block;
  for (int a = 0; a < 3; ++a) {
    for (int b = 0; b < 3; ++b) {
      block(a, b) = values[where[static_cast<std::size_t>(3 * a + b)]];
    }
  }
  return block;
}

namespace {

/// The products gather a vertex's neighbours' values into a stack buffer, at most this many
/// neighbours at a time (nearly all vertices have fewer: ~15 in a tet mesh), so that each output
/// is a contiguous dot product the compiler vectorises.
constexpr int kGatherDegree = 64;

/// Vertex c's neighbours [begin, begin + degree) and its three columns in the value array:
/// strips of 3 values per neighbour, column after column (BlockPattern's layout).
struct VertexColumns {
  int begin;
  int degree;
  const double* column0;
  const double* column1;
  const double* column2;
};

VertexColumns vertex_columns(const double* values, const int* outer, const int* offsets, int c) {
  const int begin = offsets[c];
  const int degree = offsets[c + 1] - begin;
  const double* column0 = values + outer[3 * c];
  return {begin, degree, column0, column0 + 3 * degree, column0 + 6 * degree};
}

}  // namespace

void BlockPattern::multiply(const Eigen::VectorXd& x,
                            Eigen::VectorXd& y,
                            std::span<double> chunk_dots) const {
  // Gathered (kGatherDegree), the dot products run under omp simd: a fixed order, so still
  // deterministic.
  const double* values = matrix_.valuePtr();
  const int* outer = matrix_.outerIndexPtr();
  const int* offsets = neighbour_offsets_.data();
  const int* neighbours = neighbours_.data();
  const double* in = x.data();
  double* out = y.data();
  const int chunks = num_chunks();
  const bool want_dots = !chunk_dots.empty();
#pragma omp parallel for schedule(static) if (threaded())
  for (int chunk = 0; chunk < chunks; ++chunk) {
    const int first = chunk * kChunkVertices;
    const int last = std::min(num_vertices_, first + kChunkVertices);
    double dot = 0.0;
    double gathered[3 * kGatherDegree];
    for (int c = first; c < last; ++c) {
      // Not structured bindings: clang cannot capture those in the omp simd loop.
      const VertexColumns columns = vertex_columns(values, outer, offsets, c);
      const int begin = columns.begin;
      const int degree = columns.degree;
      const double* column0 = columns.column0;
      const double* column1 = columns.column1;
      const double* column2 = columns.column2;
      double y0 = 0.0;
      double y1 = 0.0;
      double y2 = 0.0;
      if (degree <= kGatherDegree) {
        for (int slot = 0; slot < degree; ++slot) {
          const double* xn = in + 3 * neighbours[begin + slot];
          gathered[3 * slot] = xn[0];
          gathered[3 * slot + 1] = xn[1];
          gathered[3 * slot + 2] = xn[2];
        }
        const int length = 3 * degree;
#pragma omp simd reduction(+ : y0, y1, y2)
        for (int k = 0; k < length; ++k) {
          y0 += column0[k] * gathered[k];
          y1 += column1[k] * gathered[k];
          y2 += column2[k] * gathered[k];
        }
      } else {
        for (int slot = 0; slot < degree; ++slot) {
          const double* xn = in + 3 * neighbours[begin + slot];
          for (int a = 0; a < 3; ++a) {
            y0 += column0[3 * slot + a] * xn[a];
            y1 += column1[3 * slot + a] * xn[a];
            y2 += column2[3 * slot + a] * xn[a];
          }
        }
      }
      out[3 * c] = y0;
      out[3 * c + 1] = y1;
      out[3 * c + 2] = y2;
      dot += y0 * in[3 * c] + y1 * in[3 * c + 1] + y2 * in[3 * c + 2];
    }
    if (want_dots) {
      chunk_dots[static_cast<std::size_t>(chunk)] = dot;
    }
  }
}

double BlockPattern::quadratic_form(const Eigen::VectorXd& x, std::span<double> chunk_sums) const {
  // sum over c of x_c . (A_cc x_c + 2 sum over n > c of A_cn x_n).
  const int chunks = num_chunks();
#pragma omp parallel for schedule(static) if (threaded())
  for (int chunk = 0; chunk < chunks; ++chunk) {
    const int first = chunk * kChunkVertices;
    const int last = std::min(num_vertices_, first + kChunkVertices);
    double sum = 0.0;
    for (int c = first; c < last; ++c) {
      const Eigen::Map<const Eigen::Vector3d> xc(x.data() + 3 * c);
      Eigen::Vector3d upper;
      neighbour_sum(c, /*lower=*/false, x.data(), upper.data());
      sum += xc.dot(get(vertex_block(c)) * xc + 2.0 * upper);
    }
    chunk_sums[static_cast<std::size_t>(chunk)] = sum;
  }
  double total = 0.0;
  for (int chunk = 0; chunk < chunks; ++chunk) {
    total += chunk_sums[static_cast<std::size_t>(chunk)];
  }
  return total;
}

namespace {

/// K doubles side by side (GCC's and Clang's vector extension): for K = 4 one AVX register where
/// the build targets AVX (softbench_cpu.cmake), two SSE2 ones otherwise.
template <int K>
struct Lanes;
template <>
struct Lanes<2> {
  using type = Pair;
};
template <>
struct Lanes<4> {
  using type = Quad;
};

/// multiply_many()'s pass for K vectors (K = 2 or 4): per vertex and neighbour, each of the
/// neighbour's three values of the K vectors is loaded into one vector of K lanes, which each of
/// the vertex's three columns' values multiplies. (Staged through a buffer of gathered values, as
/// multiply() does, the pass took 25% longer: 8% of corotational_fem's step on the liver.)
template <int K>
void multiply_vectors(int num_vertices,
                      int num_chunks,
                      bool threaded,
                      const double* values,
                      const int* outer,
                      const int* offsets,
                      const int* neighbours,
                      const std::array<const double*, K>& in,
                      const std::array<double*, K>& out) {
  using Vector = typename Lanes<K>::type;
#pragma omp parallel for schedule(static) if (threaded)
  for (int chunk = 0; chunk < num_chunks; ++chunk) {
    const int first = chunk * BlockPattern::kChunkVertices;
    const int last = std::min(num_vertices, first + BlockPattern::kChunkVertices);
    for (int c = first; c < last; ++c) {
      const VertexColumns columns = vertex_columns(values, outer, offsets, c);
      Vector y[3] = {};
      for (int slot = 0; slot < columns.degree; ++slot) {
        const int n = neighbours[columns.begin + slot];
        for (int a = 0; a < 3; ++a) {
          Vector value;
          for (int k = 0; k < K; ++k) {
            value[k] = in[static_cast<std::size_t>(k)][3 * n + a];
          }
          const int at = 3 * slot + a;
          y[0] += columns.column0[at] * value;
          y[1] += columns.column1[at] * value;
          y[2] += columns.column2[at] * value;
        }
      }
      for (int k = 0; k < K; ++k) {
        for (int a = 0; a < 3; ++a) {
          out[static_cast<std::size_t>(k)][3 * c + a] = y[a][k];
        }
      }
    }
  }
}

template <int K>
void multiply_vectors(const BlockPattern& pattern,
                      const int* offsets,
                      const int* neighbours,
                      std::span<const Eigen::VectorXd* const> x,
                      std::span<Eigen::VectorXd* const> y) {
  std::array<const double*, K> in{};
  std::array<double*, K> out{};
  for (std::size_t k = 0; k < K; ++k) {
    in[k] = x[k]->data();
    out[k] = y[k]->data();
  }
  multiply_vectors<K>(pattern.num_vertices(), pattern.num_chunks(), pattern.threaded(),
                      pattern.matrix().valuePtr(), pattern.matrix().outerIndexPtr(), offsets,
                      neighbours, in, out);
}

}  // namespace

void BlockPattern::multiply_many(std::span<const Eigen::VectorXd* const> x,
                                 std::span<Eigen::VectorXd* const> y) const {
  if (x.size() != y.size() || x.size() > static_cast<std::size_t>(kManyVectors)) {
    throw std::invalid_argument("BlockPattern::multiply_many: x and y must pair up, at most "
                                + std::to_string(kManyVectors));
  }
  const int* offsets = neighbour_offsets_.data();
  const int* neighbours = neighbours_.data();
  switch (x.size()) {
    case 0:
      return;
    case 1:
      multiply(*x[0], *y[0]);
      return;
    case 2:
      multiply_vectors<2>(*this, offsets, neighbours, x, y);
      return;
    case 3:  // two in one pass, and the third
      multiply_vectors<2>(*this, offsets, neighbours, x, y);
      multiply(*x[2], *y[2]);
      return;
    default:
      multiply_vectors<4>(*this, offsets, neighbours, x, y);
      return;
  }
}

std::size_t BlockPattern::memory_bytes() const {
  return bytes_of_sparse(matrix_)
         + (neighbour_offsets_.size() + neighbours_.size() + mirror_slots_.size()) * sizeof(int)
         + vertex_blocks_.size() * sizeof(BlockEntries)
         + edge_blocks_.size() * 2 * sizeof(BlockEntries);
}

}  // namespace softbench
