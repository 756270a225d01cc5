// SPDX-License-Identifier: MIT
#include "models/block_pattern.h"

// GCC 12's -Wnull-dereference fires inside Eigen's inlined sparse-to-dense conversion (an outer
// index pointer it cannot prove non-null), not in this file's code.
#pragma GCC diagnostic ignored "-Wnull-dereference"

#include "geometry/mesh_topology.h"
#include "geometry/mesh_validation.h"
#include "tests/test_meshes.h"
#include "tests/test_tolerances.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <random>
#include <span>
#include <stdexcept>
#include <vector>

namespace softbench {
namespace {

/// A pattern on `edges` with symmetric random values in every block.
BlockPattern random_symmetric_pattern(int num_vertices,
                                      const Eigen::Matrix2Xi& edges,
                                      unsigned seed) {
  BlockPattern pattern(num_vertices, edges);
  std::mt19937 random(seed);
  std::uniform_real_distribution<double> entry(-1.0, 1.0);
  const auto random_block = [&] {
    Eigen::Matrix3d block;
    for (int k = 0; k < 9; ++k) {
      block(k) = entry(random);
    }
    return block;
  };
  for (int v = 0; v < num_vertices; ++v) {
    const Eigen::Matrix3d block = random_block();
    pattern.set(pattern.vertex_block(v), block + block.transpose());
  }
  for (int e = 0; e < static_cast<int>(edges.cols()); ++e) {
    const Eigen::Matrix3d block = random_block();
    pattern.set(pattern.edge_block(e), block);
    pattern.set(pattern.edge_block_transposed(e), block.transpose());
  }
  return pattern;
}

/// The same on a box of tets' edges.
BlockPattern random_symmetric_pattern(const TetMesh& mesh, unsigned seed) {
  return random_symmetric_pattern(mesh.num_vertices(), unique_edges(mesh.tets()), seed);
}

/// A star: vertex 0 joined to `leaves` others, more neighbours than one gather buffer (64) of
/// multiply() holds.
Eigen::Matrix2Xi star_edges(int leaves) {
  Eigen::Matrix2Xi star(2, leaves);
  for (int leaf = 0; leaf < leaves; ++leaf) {
    star.col(leaf) << 0, leaf + 1;
  }
  return star;
}

TEST(BlockPattern, MultiplyManyMatchesOneProductPerVector) {
  // A box of tets (~15 neighbours a vertex), and a star whose centre has 150 neighbours.
  const TetMesh mesh = make_tet_mesh(test::box_tets(4, 3, 3));
  constexpr int kLeaves = 150;
  for (const BlockPattern& pattern :
       {random_symmetric_pattern(mesh, 2),
        random_symmetric_pattern(kLeaves + 1, star_edges(kLeaves), 3)}) {
    std::vector<Eigen::VectorXd> x;
    std::vector<Eigen::VectorXd> y;
    for (int k = 0; k < BlockPattern::kManyVectors; ++k) {
      x.push_back(Eigen::VectorXd::Random(pattern.size()));
      y.push_back(Eigen::VectorXd::Zero(pattern.size()));
    }
    for (int count = 1; count <= BlockPattern::kManyVectors; ++count) {
      std::vector<const Eigen::VectorXd*> in;
      std::vector<Eigen::VectorXd*> out;
      for (int k = 0; k < count; ++k) {
        in.push_back(&x[static_cast<std::size_t>(k)]);
        out.push_back(&y[static_cast<std::size_t>(k)]);
      }
      pattern.multiply_many(in, out);
      for (int k = 0; k < count; ++k) {
        Eigen::VectorXd expected(pattern.size());
        pattern.multiply(x[static_cast<std::size_t>(k)], expected);
        EXPECT_TRUE(y[static_cast<std::size_t>(k)].isApprox(expected, test::kRoundoff))
            << count << " vectors, vector " << k;
      }
    }
  }
}

TEST(BlockPattern, MultiplyMatchesTheSparseProductAndItsDot) {
  // Large enough for several chunks (and the parallel path when threads are available).
  const TetMesh mesh = make_tet_mesh(test::box_tets(14, 12, 12));
  ASSERT_GT(mesh.num_vertices(), BlockPattern::kParallelVertices);
  const BlockPattern pattern = random_symmetric_pattern(mesh, 1);
  const Eigen::SparseMatrix<double>& matrix = pattern.matrix();
  const Eigen::SparseMatrix<double> transposed = matrix.transpose();
  ASSERT_EQ((matrix - transposed).norm(), 0.0);  // symmetric

  const Eigen::VectorXd x = Eigen::VectorXd::Random(pattern.size());
  Eigen::VectorXd y(pattern.size());
  std::vector<double> chunk_dots(static_cast<std::size_t>(pattern.num_chunks()));
  pattern.multiply(x, y, chunk_dots);
  const Eigen::VectorXd expected = matrix * x;
  EXPECT_TRUE(y.isApprox(expected, test::kRoundoff));
  double dot = 0.0;
  for (const double part : chunk_dots) {
    dot += part;
  }
  EXPECT_NEAR(dot, x.dot(expected), test::kRoundoff * std::abs(x.dot(expected)));
}

TEST(BlockPattern, QuadraticFormFromTheUpperHalfIsTheDotOfTheProduct) {
  // Several chunks (and the parallel path when threads are available), and the star's centre
  // whose blocks all lie above it (vertex 0) against leaves with none above.
  const TetMesh mesh = make_tet_mesh(test::box_tets(14, 12, 12));
  constexpr int kLeaves = 150;
  for (const BlockPattern& pattern :
       {random_symmetric_pattern(mesh, 4),
        random_symmetric_pattern(kLeaves + 1, star_edges(kLeaves), 5)}) {
    const Eigen::VectorXd x = Eigen::VectorXd::Random(pattern.size());
    const Eigen::VectorXd product = pattern.matrix() * x;
    std::vector<double> chunk_sums(static_cast<std::size_t>(pattern.num_chunks()));
    // Random blocks are indefinite: the form can cancel, so round-off is measured against the
    // sizes it is made of.
    EXPECT_NEAR(pattern.quadratic_form(x, chunk_sums), x.dot(product),
                test::kRoundoff * x.norm() * product.norm());
  }
}

TEST(BlockPattern, ColumnAndRowBlocksAreEachOthersMirror) {
  const TetMesh mesh = make_tet_mesh(test::box_tets(2, 2, 1));
  const BlockPattern pattern = random_symmetric_pattern(mesh, 2);
  const Eigen::MatrixXd dense(pattern.matrix());
  for (int v = 0; v < mesh.num_vertices(); ++v) {
    const std::span<const int> neighbours = pattern.neighbours(v);
    ASSERT_TRUE(std::is_sorted(neighbours.begin(), neighbours.end()));
    for (std::size_t slot = 0; slot < neighbours.size(); ++slot) {
      const int n = neighbours[slot];
      // column_block(v, slot) is block (n, v); row_block(v, slot) is block (v, n).
      const Eigen::Matrix3d column = dense.block<3, 3>(3 * n, 3 * v);
      const Eigen::Matrix3d row = dense.block<3, 3>(3 * v, 3 * n);
      EXPECT_EQ(pattern.get(pattern.column_block(v, static_cast<int>(slot))), column);
      EXPECT_EQ(pattern.get(pattern.row_block(v, static_cast<int>(slot))), row);
    }
  }
}

TEST(BlockPattern, TakesPartsNoBlockJoinsAndRejectsOthers) {
  // A path 0 - 1 - 2 - 3 - 4: {0, 1} and {3, 4} are parts with 2 between them as separator
  // once numbered 0, 1, 3, 4, 2; in the path's own order, {0, 1} and {2, 3} touch.
  Eigen::Matrix2Xi path(2, 4);
  path << 0, 1, 2, 3, 1, 2, 3, 4;
  BlockPattern pattern(5, path);
  EXPECT_EQ(pattern.parts(), 1);
  EXPECT_EQ(std::vector<int>(pattern.part_offsets().begin(), pattern.part_offsets().end()),
            (std::vector<int>{0, 5, 5}));
  EXPECT_THROW(pattern.set_parts({0, 2, 4, 5}), std::invalid_argument);  // 1 - 2 joins them
  EXPECT_THROW(pattern.set_parts({0, 5}), std::invalid_argument);        // no separator range
  pattern.set_parts({0, 2, 5});  // one part and a separator: a valid, if serial, order
  EXPECT_EQ(pattern.parts(), 1);
  EXPECT_THROW(pattern.set_parts({0, 3, 2, 5}), std::invalid_argument);  // not in order
  Eigen::Matrix2Xi renumbered(2, 4);  // old 0, 1, 2, 3, 4 now 0, 1, 4, 2, 3
  renumbered << 0, 1, 4, 2, 1, 4, 2, 3;
  BlockPattern cut(5, renumbered);
  cut.set_parts({0, 2, 4, 5});
  EXPECT_EQ(cut.parts(), 2);
}

}  // namespace
}  // namespace softbench
